//! A failed FMU load leaves nothing in the temporary folder (before: every failed load of a valid
//! archive with a broken description or binary left its unpack folder, up to 5.7 MB; issue #17
//! item 13), nor does an archive refused half-way through unpacking.

use fmi2::importer::Fmu;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Temporary unpack folders of archives named `stem` left by this process.
fn leftovers(stem: &str) -> Vec<PathBuf> {
    let prefix = format!("airring-{stem}-{}-", std::process::id());
    std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
        .map(|e| e.path())
        .collect()
}

/// (entry name, content) of an archive.
type Entry<'a> = (&'a str, &'a [u8]);

fn archive(path: &Path, entries: &[Entry]) {
    let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    for (name, bytes) in entries {
        z.start_file(*name, zip::write::SimpleFileOptions::default())
            .unwrap();
        z.write_all(bytes).unwrap();
    }
    z.finish().unwrap();
}

#[test]
fn failed_loads_remove_their_unpack_folders() {
    let dir = std::env::temp_dir().join(format!("importer-cleanup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = vec![7u8; 1 << 20];
    let cases: [(&str, Vec<Entry>); 3] = [
        // A readable archive whose description is not XML.
        (
            "brokenxml",
            vec![
                ("modelDescription.xml", b"<fmiModelDescription".as_slice()),
                ("resources/data.bin", &big),
            ],
        ),
        // No description at all.
        ("nodescription", vec![("resources/data.bin", &big)]),
        // An entry that would escape the folder, after one that was already written.
        (
            "escaping",
            vec![
                ("resources/data.bin", &big),
                ("../../evil.txt", b"x".as_slice()),
            ],
        ),
    ];
    for (stem, entries) in cases {
        let fmu = dir.join(format!("{stem}.fmu"));
        archive(&fmu, &entries);
        let e = Fmu::load(&fmu).err().expect("the load fails");
        assert!(e.to_string().contains(stem), "{e}");
        assert_eq!(leftovers(stem), Vec::<PathBuf>::new(), "{stem}: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
