//! The time series as Apache Parquet (`--parquet`), for pandas / pyarrow / Polars / Spark users.
//!
//! Parquet needs its footer before it can be read, so a killed run would leave nothing: the CSV
//! stays the record written as the run goes, and the Parquet file is written from the same rows
//! when the run ends (completed, failed or interrupted; a resumed run rewrites it whole).
//! One REQUIRED DOUBLE column per series (`time`, then the recorded variables by name), Snappy
//! compressed, no dictionary (floats rarely repeat); the units are in the file's key-value
//! metadata `airring.units` (JSON: column -> unit) and in each column's name in the CSV.

use parquet::basic::{Compression, Repetition, Type as PhysicalType};
use parquet::data_type::DoubleType;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::path::Path;
use std::sync::Arc;

/// Rows per row group (~13 MB of doubles for 25 columns): readers can stream a long run.
const ROW_GROUP_ROWS: usize = 65_536;

/// Writes `rows` (time, then one value per column) with the column names and units.
pub fn write(path: &Path, columns: &[(String, String)], rows: &[Vec<f64>]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let names: Vec<&str> = std::iter::once("time")
        .chain(columns.iter().map(|(n, _)| n.as_str()))
        .collect();
    let units: serde_json::Map<String, serde_json::Value> = std::iter::once(("time", "s"))
        .chain(columns.iter().map(|(n, u)| (n.as_str(), u.as_str())))
        .map(|(n, u)| {
            (
                n.to_string(),
                serde_json::json!(if u.is_empty() { "1" } else { u }),
            )
        })
        .collect();
    if let Some(r) = rows.iter().find(|r| r.len() != names.len()) {
        return Err(err(&format!(
            "a row has {} values for {} columns",
            r.len(),
            names.len()
        )));
    }
    let fields = names
        .iter()
        .map(|n| {
            Type::primitive_type_builder(n, PhysicalType::DOUBLE)
                .with_repetition(Repetition::REQUIRED)
                .build()
                .map(Arc::new)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| err(&e))?;
    let schema = Type::group_type_builder("airring_timeseries")
        .with_fields(fields)
        .build()
        .map_err(|e| err(&e))?;
    let props = WriterProperties::builder()
        .set_compression(Compression::SNAPPY)
        .set_dictionary_enabled(false)
        .set_key_value_metadata(Some(vec![KeyValue::new(
            "airring.units".to_string(),
            serde_json::Value::Object(units).to_string(),
        )]))
        .build();
    // Written whole or not at all (a temporary file renamed into place): a full disk or a kill
    // never leaves a truncated file under the final name, and a link there is replaced.
    cosim::files::write_whole_with(path, |f| {
        write_rows(f.try_clone()?, schema, props, rows).map_err(std::io::Error::other)
    })
    .map_err(|e| err(&e))
}

fn write_rows(
    file: std::fs::File,
    schema: Type,
    props: parquet::file::properties::WriterProperties,
    rows: &[Vec<f64>],
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut w =
        SerializedFileWriter::new(file, Arc::new(schema), Arc::new(props)).map_err(|e| err(&e))?;
    let mut column = Vec::with_capacity(ROW_GROUP_ROWS.min(rows.len()));
    for group in rows.chunks(ROW_GROUP_ROWS) {
        let mut rg = w.next_row_group().map_err(|e| err(&e))?;
        let mut k = 0;
        while let Some(mut col) = rg.next_column().map_err(|e| err(&e))? {
            column.clear();
            column.extend(group.iter().map(|r| r[k]));
            col.typed::<DoubleType>()
                .write_batch(&column, None, None)
                .map_err(|e| err(&e))?;
            col.close().map_err(|e| err(&e))?;
            k += 1;
        }
        rg.close().map_err(|e| err(&e))?;
    }
    w.into_inner().map(|_| ()).map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::RowAccessor;

    /// Read back with the crate's independent reader: names, units, every value bit for bit,
    /// across row groups.
    #[test]
    fn round_trip_through_a_reader() {
        let dir = std::env::temp_dir().join(format!("airring-pq-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ts.parquet");
        let cols = [
            ("rotor.omega".to_string(), "rad/s".to_string()),
            ("film_C.eps".to_string(), String::new()),
        ];
        let n = ROW_GROUP_ROWS + 17;
        let rows: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                let t = i as f64 * 5e-5;
                vec![
                    t,
                    2.0 * std::f64::consts::PI * 2000.0 * t / 3.0,
                    (t * 1e3).sin() / 3.0,
                ]
            })
            .collect();
        write(&path, &cols, &rows).unwrap();

        let reader = SerializedFileReader::new(std::fs::File::open(&path).unwrap()).unwrap();
        let meta = reader.metadata();
        assert_eq!(meta.num_row_groups(), 2);
        assert_eq!(meta.file_metadata().num_rows(), n as i64);
        let schema = meta.file_metadata().schema_descr();
        let names: Vec<String> = (0..3)
            .map(|i| schema.column(i).name().to_string())
            .collect();
        assert_eq!(names, ["time", "rotor.omega", "film_C.eps"]);
        let kv = meta.file_metadata().key_value_metadata().unwrap();
        let units: serde_json::Value =
            serde_json::from_str(kv[0].value.as_deref().unwrap()).unwrap();
        assert_eq!(units["time"], "s");
        assert_eq!(units["rotor.omega"], "rad/s");
        assert_eq!(units["film_C.eps"], "1");
        let mut count = 0;
        for (row, expected) in reader.get_row_iter(None).unwrap().zip(&rows) {
            let row = row.unwrap();
            for (k, x) in expected.iter().enumerate() {
                assert_eq!(row.get_double(k).unwrap().to_bits(), x.to_bits());
            }
            count += 1;
        }
        assert_eq!(count, n);
        // A row of the wrong width is refused with the file named.
        let e = write(&path, &cols, &[vec![0.0, 1.0]]).unwrap_err();
        assert!(
            e.contains("ts.parquet") && e.contains("2 values for 3 columns"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
