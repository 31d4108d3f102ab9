//! FMU states as byte blobs (fmi2SerializeFMUstate / fmi2DeSerializeFMUstate, and FMI 3.0's
//! fmi3SerializeFMUState / fmi3DeserializeFMUState: one format for both).
//!
//! Layout: magic, format version, the FMU's GUID, the payload length, the payload (instance core and
//! the model's own bytes), and an FNV-1a checksum of all of it. Truncated, foreign or corrupted bytes
//! are refused with a reason; they never reach the model.

use crate::instance::{Core, Phase};
use crate::model::{Model, Store, MAX_INPUT_DERIVATIVE_ORDER};
use crate::variables::Fnv64;

const MAGIC: &[u8; 16] = b"AIRRING FMUSTATE";
const FORMAT_VERSION: u32 = 1;

/// Little-endian byte writer.
#[derive(Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    pub fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    pub fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    pub fn opt_f64(&mut self, x: Option<f64>) {
        self.u8(x.is_some() as u8);
        self.f64(x.unwrap_or(0.0));
    }
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.0.extend_from_slice(b);
    }
}

/// Bounds-checked reader: every read reports truncation instead of panicking.
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Reader { data, pos: 0 }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.data.len())
            .ok_or("the FMU state is truncated")?;
        let s = &self.data[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    pub fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    pub fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn opt_f64(&mut self) -> Result<Option<f64>, String> {
        let some = self.u8()? != 0;
        let x = self.f64()?;
        Ok(some.then_some(x))
    }
    pub fn bytes(&mut self) -> Result<&'a [u8], String> {
        let n = usize::try_from(self.u64()?).map_err(|_| "length overflow")?;
        self.take(n)
    }
    pub fn len_checked(&mut self, expected: usize, what: &str) -> Result<(), String> {
        let n = self.u64()?;
        if n != expected as u64 {
            return Err(format!(
                "the FMU state holds {n} {what}, this FMU has {expected}"
            ));
        }
        Ok(())
    }
    pub fn finished(&self) -> bool {
        self.pos == self.data.len()
    }
}

pub fn serialize<M: Model>(core: &Core<M>, guid: &str) -> Vec<u8> {
    let mut p = Writer::default();
    p.u8(core.phase.to_u8());
    p.f64(core.time);
    p.f64(core.start_time);
    p.opt_f64(core.stop_time);
    p.opt_f64(core.tolerance);
    p.f64(core.last_successful_time);
    p.u8(core.model_stale as u8);
    let s = &core.store;
    p.u64(s.reals.len() as u64);
    s.reals.iter().for_each(|x| p.f64(*x));
    p.u64(s.integers.len() as u64);
    s.integers.iter().for_each(|x| p.u32(*x as u32));
    p.u64(s.booleans.len() as u64);
    s.booleans.iter().for_each(|x| p.u8(*x as u8));
    p.u64(core.input_derivatives.len() as u64);
    core.input_derivatives
        .iter()
        .flatten()
        .for_each(|x| p.f64(*x));
    match &core.model {
        Some(m) => {
            p.u8(1);
            p.bytes(&m.serialize());
        }
        None => p.u8(0),
    }

    let mut w = Writer::default();
    w.0.extend_from_slice(MAGIC);
    w.u32(FORMAT_VERSION);
    w.bytes(guid.as_bytes());
    w.bytes(&p.0);
    let mut h = Fnv64::new();
    h.write(&w.0);
    w.u64(h.finish());
    w.0
}

pub fn deserialize<M: Model>(data: &[u8], guid: &str, shape: &Store) -> Result<Core<M>, String> {
    if data.len() < MAGIC.len() + 8 || &data[..MAGIC.len()] != MAGIC {
        return Err("the bytes are not an AirRing FMU state".into());
    }
    let (body, sum) = data.split_at(data.len() - 8);
    let mut h = Fnv64::new();
    h.write(body);
    if h.finish().to_le_bytes() != sum {
        return Err("the FMU state is truncated or corrupted (checksum mismatch)".into());
    }
    let mut r = Reader::new(&body[MAGIC.len()..]);
    let version = r.u32()?;
    if version != FORMAT_VERSION {
        return Err(format!(
            "FMU state format version {version} is not supported (expected {FORMAT_VERSION})"
        ));
    }
    let their_guid = r.bytes()?;
    if their_guid != guid.as_bytes() {
        return Err(format!(
            "the FMU state belongs to another FMU (GUID {})",
            String::from_utf8_lossy(their_guid)
        ));
    }
    let payload = r.bytes()?;
    if !r.finished() {
        return Err("trailing bytes after the FMU state".into());
    }
    let mut p = Reader::new(payload);
    let phase = Phase::from_u8(p.u8()?).ok_or("unknown instance phase in the FMU state")?;
    let time = p.f64()?;
    let start_time = p.f64()?;
    let stop_time = p.opt_f64()?;
    let tolerance = p.opt_f64()?;
    let last_successful_time = p.f64()?;
    let model_stale = p.u8()? != 0;
    let mut store = shape.clone();
    p.len_checked(store.reals.len(), "Real values")?;
    for x in &mut store.reals {
        *x = p.f64()?;
    }
    p.len_checked(store.integers.len(), "Integer values")?;
    for x in &mut store.integers {
        *x = p.u32()? as i32;
    }
    p.len_checked(store.booleans.len(), "Boolean values")?;
    for x in &mut store.booleans {
        *x = p.u8()? != 0;
    }
    p.len_checked(store.reals.len(), "input derivative rows")?;
    let mut input_derivatives = vec![[0.0; MAX_INPUT_DERIVATIVE_ORDER]; store.reals.len()];
    for row in &mut input_derivatives {
        for x in row.iter_mut() {
            *x = p.f64()?;
        }
    }
    let model = match p.u8()? {
        0 => None,
        1 => Some(
            M::deserialize(p.bytes()?).map_err(|e| format!("the model state is invalid: {e}"))?,
        ),
        _ => return Err("bad model flag in the FMU state".into()),
    };
    if !p.finished() {
        return Err("trailing bytes in the FMU state payload".into());
    }
    Ok(Core {
        phase,
        store,
        model,
        model_stale,
        time,
        start_time,
        stop_time,
        tolerance,
        last_successful_time,
        input_derivatives,
    })
}
