//! Property tests of the UFF (dataset 58/58b) and WAV readers and of the format sniffing
//! (proptest, issue 33): random bytes behind a format's first bytes, and valid files (the
//! shipped fixtures, written by pyuff and Python's `wave`) mutated and truncated, never panic;
//! every error is bad input (exit code 2) on one line naming the file. Each case is a few tens
//! of KB read once or twice: the reader's work is bounded by the file (a header that claims
//! more values than the file holds ends at the file's end with an error).
//!
//! Cases per property: 64 in the normal test run; set STICKSLIP_FUZZ_CASES for a longer run.

use proptest::prelude::*;
use stickslip::error::HostError;
use stickslip::recorded::analysis::{AnalysisConfig, FloorSource};
use stickslip::recorded::channels::ChannelMap;
use stickslip::recorded::{analyze_with, ReadOptions};

fn cases() -> u32 {
    std::env::var("STICKSLIP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(64)
}

fn cfg(floor: FloorSource) -> AnalysisConfig {
    AnalysisConfig {
        from_s: f64::NEG_INFINITY,
        segment: Some(64),
        breakaway_jump_m_s2: 33.17,
        floor,
        face_coefficient: 0.0,
        band_speed_m_s: 0.005,
        figures: true,
        spectra: true,
        windows: true,
    }
}

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!("{}/tests/data/recordings/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// Writes `bytes` to a scratch file and analyses it (the floor found anywhere: two passes);
/// any error must be `Input`, one line, naming the file.
fn no_panic(name: &str, bytes: &[u8], map: &[&str]) {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-formats");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}-{}", std::thread::current().name().unwrap_or("t").replace("::", "_")));
    std::fs::write(&path, bytes).unwrap();
    let label = path.to_str().unwrap().to_string();
    let opts = ReadOptions {
        channels: ChannelMap::parse(&map.iter().map(|s| s.to_string()).collect::<Vec<_>>()).unwrap(),
        ..ReadOptions::default()
    };
    for floor in [FloorSource::Auto, FloorSource::Jump] {
        match analyze_with(&label, cfg(floor), &opts) {
            Ok(a) => {
                assert!(a.samples >= 1);
                for (c, s) in a.channels.iter().enumerate() {
                    if a.present[c] {
                        assert!(s.pp.is_finite() && s.pp >= 0.0 && s.rms.is_finite() && s.groan_rms.is_finite());
                    }
                }
            }
            Err(HostError::Input(m)) => {
                assert!(m.starts_with(&format!("{label}: ")), "{m}");
                assert_eq!(HostError::Input(m.clone()).to_string().lines().count(), 1, "{m}");
            }
            Err(e) => panic!("not an input error: {e:?}"),
        }
    }
}

const WAV_MAP: [&str; 4] = ["pad_x=#1*8", "pad_trail=#2*8", "disc_x=#3*8", "pad_lead=#4*8"];

/// A mutation: overwrite `n` bytes at `at` (fractions of the length) with `with`, then keep
/// the first `keep` (a fraction) of the file.
fn mutate(mut b: Vec<u8>, at: &[(f64, u8)], keep: f64) -> Vec<u8> {
    let n = b.len();
    for (f, v) in at {
        let i = ((f * n as f64) as usize).min(n - 1);
        b[i] = *v;
    }
    b.truncate(((keep * n as f64) as usize).max(1));
    b
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_after_a_uff_start_never_panic(tail in proptest::collection::vec(any::<u8>(), 0..2048), binary in any::<bool>()) {
        let mut b = if binary { b"    -1\n    58b     1     2          11         400     0     0           0           0\n".to_vec() } else { b"    -1\n    58\n".to_vec() };
        b.extend(tail);
        no_panic("random.uff", &b, &[]);
    }

    #[test]
    fn random_lines_in_a_uff_header_never_panic(line in 0usize..14, text in "[ 0-9eE+.\\-a-z/^]{0,90}", which in 0usize..3) {
        let name = ["rec_58.uff", "rec_58b_single.uff", "rec_58b_double.uff"][which];
        let b = fixture(name);
        // replace one of the first record's 13 lines (the delimiter, the id line, records 1-11)
        let mut parts: Vec<&[u8]> = b.splitn(15, |&c| c == b'\n').collect();
        let t = text.into_bytes();
        parts[line] = &t;
        no_panic(name, &parts.join(&b'\n'), &[]);
    }

    #[test]
    fn mutated_and_truncated_uff_never_panics(at in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..8), keep in 0.0f64..1.0, which in 0usize..3) {
        let name = ["rec_58.uff", "rec_58b_single.uff", "rec_58b_double.uff"][which];
        no_panic(name, &mutate(fixture(name), &at, keep), &[]);
    }

    #[test]
    fn random_bytes_after_a_wav_start_never_panic(tail in proptest::collection::vec(any::<u8>(), 0..2048)) {
        let mut b = b"RIFF\x24\x10\0\0WAVEfmt ".to_vec();
        b.extend(tail);
        no_panic("random.wav", &b, &WAV_MAP);
    }

    #[test]
    fn mutated_and_truncated_wav_never_panics(at in proptest::collection::vec((0.0f64..0.01, any::<u8>()), 0..6), keep in 0.0f64..1.0) {
        no_panic("rec.wav", &mutate(fixture("rec.wav"), &at, keep), &WAV_MAP);
    }
}
