//! The shipped defmt fixture (`tests/data/defmt-fixture.{elf,defmt}`: one record of every kind,
//! see recorded_decode.rs) and its frames, shared by `recorded_decode` and `record`.

/// The firmware ELF the fixture's stream was logged with.
pub const ELF: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.elf");
/// The fixture's raw defmt stream.
pub const STREAM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.defmt");

/// Frames in the fixture (13 records and one plain line).
pub const FRAMES: usize = 14;

/// The kind of each frame of the fixture, in order (two `command` records).
pub const FRAME_KINDS: [&str; FRAMES] = [
    "boot",
    "config_error",
    "armed",
    "start",
    "state",
    "command",
    "command",
    "event",
    "window",
    "overrun",
    "stall",
    "input",
    "panic",
    "log",
];

/// The fixture's kinds in order, each once.
pub fn kinds() -> Vec<&'static str> {
    let mut k = FRAME_KINDS.to_vec();
    k.dedup();
    k
}

/// The ELF's and the stream's bytes.
pub fn fixture() -> (Vec<u8>, Vec<u8>) {
    (std::fs::read(ELF).unwrap(), std::fs::read(STREAM).unwrap())
}

/// (offset, length) of every frame: the non-empty runs of non-zero bytes ended by a zero (the
/// rzCOBS rule, read off the bytes).
pub fn frames(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &b) in bytes.iter().enumerate() {
        match (b, start) {
            (0, Some(s)) => {
                out.push((s, i - s));
                start = None;
            }
            (0, None) => {}
            (_, None) => start = Some(i),
            (_, Some(_)) => {}
        }
    }
    out
}
