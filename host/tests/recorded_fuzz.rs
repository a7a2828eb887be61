//! Property tests of the recording reader and analysis (proptest): random bytes and mutated
//! valid files never panic, and every error is bad input (exit code 2) on one line naming the
//! file; random valid files give the peak-to-peak and RMS computed here from the values
//! written.
//!
//! Cases per property: 256 in the normal test run; set STICKSLIP_FUZZ_CASES for a longer run
//! (e.g. 100000).

use proptest::prelude::*;
use stickslip::error::HostError;
use stickslip::recorded::analysis::AnalysisConfig;
use stickslip::recorded::analyze_reader;

fn cases() -> u32 {
    std::env::var("STICKSLIP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(256)
}

fn cfg() -> AnalysisConfig {
    AnalysisConfig {
        from_s: f64::NEG_INFINITY,
        segment: Some(64),
        breakaway_jump_m_s2: 33.17,
        floor: stickslip::recorded::analysis::FloorSource::Jump,
        face_coefficient: 0.0,
        band_speed_m_s: 0.005,
        figures: true,
        spectra: true,
        windows: true,
    }
}

/// Runs the analysis; any error must be `Input`, one line, naming the file.
fn no_panic(bytes: &[u8]) {
    match analyze_reader("fuzz.csv", bytes, cfg()) {
        Ok(a) => {
            assert!(a.samples >= 1);
            for c in &a.channels {
                assert!(c.pp.is_finite() && c.pp >= 0.0 && c.rms.is_finite());
            }
        }
        Err(HostError::Input(m)) => {
            assert!(m.starts_with("fuzz.csv: "), "{m}");
            let shown = HostError::Input(m.clone()).to_string();
            assert_eq!(shown.lines().count(), 1, "{m}");
        }
        Err(e) => panic!("not an input error: {e:?}"),
    }
}

/// A valid semicolon export of `n` rows at 2 kHz.
fn valid(n: usize) -> Vec<u8> {
    let mut s = String::from("\"time [s]\";disc_x;pad_x (m/s²);pad_trail;pad_lead\r\n");
    for i in 0..n {
        s.push_str(&format!(
            "{};{};-{};1,5;{}e-1\r\n",
            format!("{:.6}", i as f64 / 2000.0).replace('.', ","),
            (i % 7) as f64 * 0.25,
            (i % 5) * 3,
            i % 11
        ));
    }
    s.push_str(";;;;\r\n\r\n");
    s.into_bytes()
}

#[derive(Debug, Clone)]
enum Mutation {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize, usize),
    Truncate(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
        (any::<usize>(), prop::sample::select(b";,.\"\n\r-e0123456789 \t".to_vec())).prop_map(|(i, b)| Mutation::Insert(i, b)),
        (any::<usize>(), 1usize..40).prop_map(|(i, n)| Mutation::Delete(i, n)),
        any::<usize>().prop_map(Mutation::Truncate),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
    ]
}

fn apply(mut v: Vec<u8>, m: &Mutation) -> Vec<u8> {
    let n = v.len().max(1);
    match *m {
        Mutation::Flip(i, b) => {
            let i = i % n;
            if i < v.len() {
                v[i] = b;
            }
        }
        Mutation::Insert(i, b) => v.insert(i % (v.len() + 1), b),
        Mutation::Delete(i, k) => {
            let i = i % n;
            let j = (i + k).min(v.len());
            if i < j {
                v.drain(i..j);
            }
        }
        Mutation::Truncate(i) => v.truncate(i % n),
        Mutation::DuplicateLine(i) | Mutation::SwapLines(i, _) => {
            let mut lines: Vec<Vec<u8>> = v.split(|&b| b == b'\n').map(|l| l.to_vec()).collect();
            let k = i % lines.len();
            if let Mutation::SwapLines(_, j) = *m {
                let j = j % lines.len();
                lines.swap(k, j);
            } else {
                let l = lines[k].clone();
                lines.insert(k, l);
            }
            v = lines.join(&b'\n');
        }
    }
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        no_panic(&bytes);
    }

    #[test]
    fn random_text_after_a_valid_header_never_panics(
        body in prop::collection::vec(prop::sample::select(b";,.\"\n\r-+eE0123456789 \tx".to_vec()), 0..800)
    ) {
        let mut v = b"t;disc_x;pad_x;pad_trail;pad_lead\n".to_vec();
        v.extend_from_slice(&body);
        no_panic(&v);
    }

    #[test]
    fn mutated_valid_files_never_panic(ms in prop::collection::vec(mutation(), 1..6), n in 0usize..300) {
        let mut v = valid(n);
        for m in &ms {
            v = apply(v, m);
        }
        no_panic(&v);
    }

    #[test]
    fn valid_files_give_the_written_statistics(
        vals in prop::collection::vec((-99_999i32..=99_999, -9_999i32..=9_999), 2..400),
        comma in any::<bool>(),
    ) {
        // pad_x = a / 1000 and pad_lead = b / 100, the others 0; time at 2 kHz to 1 us
        let (sep, dec) = if comma { (";", ",") } else { (",", ".") };
        let mut s = format!("t{sep}pad_x{sep}disc_x{sep}pad_trail{sep}pad_lead\n");
        for (i, (a, b)) in vals.iter().enumerate() {
            let t = format!("{:.6}", i as f64 / 2000.0);
            let x = format!("{:.3}", *a as f64 / 1000.0);
            let y = format!("{:.2}", *b as f64 / 100.0);
            s.push_str(&[t, x, "0".into(), "0".into(), y].map(|c| c.replace('.', dec)).join(sep));
            s.push('\n');
        }
        let an = analyze_reader("fuzz.csv", s.as_bytes(), cfg()).unwrap();
        let (amax, amin) = (vals.iter().map(|v| v.0).max().unwrap(), vals.iter().map(|v| v.0).min().unwrap());
        let (bmax, bmin) = (vals.iter().map(|v| v.1).max().unwrap(), vals.iter().map(|v| v.1).min().unwrap());
        prop_assert!((an.channels[1].pp - (amax - amin) as f64 / 1000.0).abs() < 1e-9);
        prop_assert!((an.channels[3].pp - (bmax - bmin) as f64 / 100.0).abs() < 1e-9);
        let ms: f64 = vals.iter().map(|v| (v.0 as f64 / 1000.0).powi(2)).sum::<f64>() / vals.len() as f64;
        prop_assert!((an.channels[1].rms - ms.sqrt()).abs() < 1e-9);
        prop_assert_eq!(an.channels[0].pp, 0.0);
        prop_assert_eq!(an.samples as usize, vals.len());
    }
}
