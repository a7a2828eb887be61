//! The contact estimate (stick fraction, stick-slip frequency) is not told where it would be a
//! guess: each class of record that gave a confident wrong figure before (a campaign of
//! synthetic recordings against their constructed truth), with the estimate now null and the
//! reason named, beside a control record of the same kind that is still told right.
//!
//! The records are built here: stick phases of noise only and slips whose pad acceleration is
//! a_rel = -J cos(pi tau / T_slip) (the jump J at breakaway, the velocity -J T_slip / pi
//! sin(pi tau / T_slip) back to zero at the slip's end), so the true stick fraction is the
//! share of rows in the stick phases.

mod recorded_common;

use recorded_common::*;
use serde_json::Value;

/// A stick-slip record: `fs` [Hz], `secs` [s], cycles of `f_ss` [Hz] with stick fraction `sf`
/// (the stick first), jump `j` [m/s^2], noise `sigma` [m/s^2] on every channel, `offset`
/// [m/s^2] added to pad_x. Returns the CSV and the true stick fraction.
fn stick_slip(fs: f64, secs: f64, f_ss: f64, sf: f64, j: f64, sigma: f64, offset: f64) -> (String, f64) {
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    stick_slip_with(fs, secs, f_ss, sf, j, offset, |_| noise.gauss(sigma))
}

/// [`stick_slip`] with the noise of channel `c` (0 disc_x, 1 pad_x, 2 pad_trail, 3 pad_lead)
/// from `noise(c)`.
fn stick_slip_with(fs: f64, secs: f64, f_ss: f64, sf: f64, j: f64, offset: f64, mut noise: impl FnMut(usize) -> f64) -> (String, f64) {
    let n = (fs * secs).round() as usize;
    let period = 1.0 / f_ss;
    let t_slip = (1.0 - sf) * period;
    let mut csv = String::from("t_s,disc_x_m_s2,pad_x_m_s2,pad_trail_m_s2,pad_lead_m_s2\n");
    let mut stick_rows = 0;
    for i in 0..n {
        let t = i as f64 / fs;
        let phase = t % period;
        let a = if phase < sf * period {
            stick_rows += 1;
            0.0
        } else {
            -j * (std::f64::consts::PI * (phase - sf * period) / t_slip).cos()
        };
        // the edge sensors: the pad's rotation, 0.6 and -0.8 of its x acceleration
        let (d, p, tr, le) = (noise(0), noise(1), noise(2), noise(3));
        csv += &format!("{t:.9},{d:.6},{:.6},{:.6},{:.6}\n", a + offset + p, 0.6 * a + tr, -0.8 * a + le);
    }
    (csv, stick_rows as f64 / n as f64)
}

fn analyze(dir: &std::path::Path, name: &str, csv: &str) -> Value {
    let f = write(dir, name, csv);
    json(&["analyze", &f, "--json"])
}

fn undecided(v: &Value) -> String {
    assert!(v["stick_fraction"].is_null() && v["stick_slip_hz"].is_null(), "told: {} / {}", v["stick_fraction"], v["stick_slip_hz"]);
    v["estimator"]["undecided"].as_str().expect("a reason").to_string()
}

fn told(v: &Value, truth: f64) {
    assert!(v["estimator"]["undecided"].is_null(), "{}", v["estimator"]["undecided"]);
    let sf = v["stick_fraction"].as_f64().unwrap();
    assert!((sf - truth).abs() <= 0.02, "stick fraction {sf} vs {truth}");
}

#[test]
fn an_offset_pad_x_makes_a_slip_that_never_ends_and_is_not_told() {
    let dir = scratch("not-told-offset");
    // control: no offset, told right
    let (csv, truth) = stick_slip(25_600.0, 1.0, 50.0, 0.5, 10.0, 0.01, 0.0);
    told(&analyze(&dir, "clean.csv", &csv), truth);
    // pad_x 5 m/s^2 off (half the jump): the estimator integrated the offset through one slip
    // (it gave 0.002 for 0.5)
    // (its stick rows sit 5 m/s^2 from zero, so the quietest blocks of a_rel are the slip's
    // crossings of zero: ramps, no floor; before the floor's trend test they were taken for
    // one, and the sliding velocity's drift refused the estimate later)
    let (csv, _) = stick_slip(25_600.0, 1.0, 50.0, 0.5, 10.0, 0.01, 5.0);
    let v = analyze(&dir, "offset.csv", &csv);
    let why = undecided(&v);
    let floor = v["estimator"]["floor_note"].as_str().unwrap_or("");
    assert!((why.contains("sliding velocity") && why.contains("m/s")) || floor.contains("straight lines"), "{why} / {floor}");
}

#[test]
fn stick_phases_shorter_than_a_floor_block_give_no_floor_of_slip_rows() {
    let dir = scratch("not-told-short-stick");
    // 2 kHz, 20 Hz, stick fraction 0.3: 30-row stick phases, shorter than the floor's 32-row
    // blocks. The campaign's record (data/recordings/make_short_stick.py, numpy): the floor was
    // taken in slips (sigma 2.9 for 0.014), no onset, all stick (it gave 1.0 for 0.305)
    let f = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/recordings/short_stick_2khz.csv");
    let v = json(&["analyze", f, "--json"]);
    assert_eq!(v["estimator"]["thresholds_from"], "floor");
    let why = undecided(&v);
    assert!(why.contains("noise floor's sigma"), "{why}");
    // the same kind of record built here (its noise draws differ): no floor found, not told
    let (csv, _) = stick_slip(2_000.0, 2.0, 20.0, 0.3, 10.0, 0.01, 0.0);
    undecided(&analyze(&dir, "short.csv", &csv));
    // control: the same at 5 Hz (100-row stick phases), told right
    let (csv, truth) = stick_slip(2_000.0, 4.0, 5.0, 0.5, 10.0, 0.01, 0.0);
    told(&analyze(&dir, "long.csv", &csv), truth);
}

#[test]
fn pure_noise_is_not_stick_slip() {
    let dir = scratch("not-told-noise");
    // Gaussian noise of 3, 5 and 7 m/s^2 on both channels: no quiet rows, the scene's
    // thresholds, and noise peaks crossing them (it gave 466 Hz at 5 m/s^2)
    for sigma in [3.0, 5.0, 7.0] {
        let (csv, _) = stick_slip(25_600.0, 1.0, 50.0, 0.5, 0.0, sigma, 0.0);
        let v = analyze(&dir, &format!("noise{sigma}.csv"), &csv);
        let why = undecided(&v);
        eprintln!("noise {sigma}: {why}");
    }
}

#[test]
fn the_virtual_rig_does_not_tell_what_its_front_end_cannot_resolve() {
    // noise 10 m/s^2 against a pad_x of 80 m/s^2 peak-to-peak: no quiet lead found and the
    // estimator never starts (it gave 0.0 for 0.805)
    let v = json(&["sil", "push_center", "--noise", "10", "--json"]);
    assert!(v["stick_fraction"]["estimated"].is_null(), "{}", v["stick_fraction"]);
    assert!(v["undecided"].is_string(), "{v}");
    // a front-end gain of 0.001 and 0.003: 79 and 26 m/s^2 a count, pad_x 1 to 3 counts (it
    // gave 1.0 and 0.983 for 0.805)
    for gain in ["0.001", "0.003"] {
        let v = json(&["sil", "push_center", "--gain", gain, "--json"]);
        assert!(v["stick_fraction"]["estimated"].is_null(), "gain {gain}: {}", v["stick_fraction"]);
        assert!(v["undecided"].as_str().unwrap().contains("converter's count"), "gain {gain}: {}", v["undecided"]);
    }
    // thesis-mu (mu_k = mu_s): the pad ends up sliding with an oscillation; the estimator's
    // velocity crossed zero 65 times between "sticks" of 3 rows (it gave 130 Hz for none)
    let v = json(&["sil", "thesis-mu", "--json"]);
    assert!(v["stick_slip_hz"]["estimated"].is_null(), "{}", v["stick_slip_hz"]);
    assert!(v["undecided"].as_str().unwrap().contains("sticks of"), "{}", v["undecided"]);
    // control: the default front end, told right
    let v = json(&["sil", "push_center", "--json"]);
    let sf = &v["stick_fraction"];
    assert!((sf["estimated"].as_f64().unwrap() - sf["true"].as_f64().unwrap()).abs() <= 0.02, "{sf}");
}

#[test]
fn noise_near_the_onset_level_splits_slips_and_is_not_told() {
    // The virtual rig with noise whose onset level (6 sigma of a_rel) nears the slips' own
    // a_rel (push_center's breakaway jump is about 33 m/s^2): slips are split in two (a false
    // re-stick a few ms after the onset, then a second onset) or onsets taken from noise. Before,
    // the estimate was told and wrong: `sil push_center --noise 5` gave 69.7 Hz for 48.6 and a
    // stick fraction of 0.719 for 0.805, `pull_lead --noise 3` 91.3 Hz for 61.9,
    // `pull_trail --noise 5 --seed 4` +6.2 %. Wherever it is told now it is right (the frequency
    // within 5 %, the stick fraction within 0.05 of the model's own); where it is not, a reason
    // is named. (Left alone: `pull_lead --noise 4 --seed 1`, whose slips stay below the onset
    // level: two onsets from noise peaks in the window, 3.8 Hz for 61.9.)
    let mut not_told = vec![];
    for (case, noise) in [("push_center", "4"), ("push_center", "4.5"), ("push_center", "5"), ("pull_lead", "3"), ("pull_trail", "5"), ("push_trail", "3.5")] {
        for seed in ["1", "2", "3", "4"] {
            let v = json(&["sil", case, "--noise", noise, "--seed", seed, "--json"]);
            let (hz, sf) = (&v["stick_slip_hz"], &v["stick_fraction"]);
            match (hz["estimated"].as_f64(), sf["estimated"].as_f64()) {
                (Some(h), Some(f)) => {
                    let (ht, ft) = (hz["true"].as_f64().unwrap(), sf["true"].as_f64().unwrap());
                    assert!((h - ht).abs() <= 0.05 * ht && (f - ft).abs() <= 0.05, "{case} --noise {noise} --seed {seed}: {h} Hz for {ht}, {f} for {ft}");
                }
                _ => {
                    let why = v["undecided"].as_str().unwrap_or_else(|| panic!("{case} {noise} {seed}: no reason: {v}"));
                    not_told.push((case, noise, seed, why.to_string()));
                }
            }
        }
    }
    // the campaign's record among them, with the new reason
    let (_, _, _, why) = not_told.iter().find(|(c, n, s, _)| (*c, *n, *s) == ("push_center", "5", "1")).expect("push_center --noise 5 not told");
    assert!(why.contains("intervals between slip onsets are far from their median") && why.contains("under a third of it"), "{why}");
    // onsets missed or added at another scale: the 1-DOF oracle's slow slips (0.86 Hz), cut in
    // two by the estimator's drift guard at a front-end gain of 2 (it gave 1.72 Hz, exactly
    // twice the truth, with the stick fraction right)
    let v = json(&["sil", "oracle_1dof", "--gain", "2", "--json"]);
    assert!(v["stick_slip_hz"]["estimated"].is_null(), "{}", v["stick_slip_hz"]);
    let why = v["undecided"].as_str().unwrap();
    assert!(why.contains("far from their median"), "{why}");
    // control: the same cases at noise 2, told right, no interval short
    for case in ["push_center", "pull_lead", "pull_trail", "push_trail"] {
        let v = json(&["sil", case, "--noise", "2", "--json"]);
        let (h, ht) = (v["stick_slip_hz"]["estimated"].as_f64().unwrap(), v["stick_slip_hz"]["true"].as_f64().unwrap());
        assert!((h - ht).abs() <= 1e-3 * ht, "{case}: {h} for {ht}");
    }
}

#[test]
fn the_intervals_between_onsets_are_reported_with_their_spread() {
    let dir = scratch("not-told-intervals");
    // 50 Hz for 2 s: 99 intervals of 20 ms exactly (the record's construction)
    let (csv, truth) = stick_slip(25_600.0, 2.0, 50.0, 0.5, 10.0, 0.01, 0.0);
    let v = analyze(&dir, "regular.csv", &csv);
    told(&v, truth);
    let i = &v["estimator"]["onset_intervals"];
    assert_eq!(i["count"], 99, "{i}");
    assert!((i["mean_s"].as_f64().unwrap() - 0.02).abs() <= 2.0 / 25_600.0, "{i}");
    assert!(i["sd_s"].as_f64().unwrap() <= 1.0 / 25_600.0, "{i}");
    assert!((i["median_s"].as_f64().unwrap() / 0.02).log2().abs() <= 1.0 / 32.0, "{i}");
    assert_eq!(i["under_a_third_of_median"], 0, "{i}");
    let md = ok(&["analyze", &write(&dir, "regular2.csv", &csv)]);
    assert!(md.contains("Intervals between slip onsets: 99, mean 20.0"), "{md}");
}

/// A slow sine on pad_x (3 Hz, 8 m/s^2, the disc still) with 0.02 m/s^2 of noise at 6.4 kHz
/// never sticks: a_rel is the sine, at the noise level nowhere. Its quietest blocks are its zero
/// crossings, ramps of about 0.75 m/s^2 a block, which the floor search took for stick's noise
/// (sigma 0.355): the estimator then read each crossing as a stick phase and told stick-slip at
/// 6.01 Hz with a stick fraction of 0.054 (a campaign). The floor's blocks are now tested for
/// being straight lines; a control with stick phases of noise band-limited far below the
/// sampling rate (a 2-pole low-pass at 2 kHz, sampled at 51.2 kHz: a line takes a larger share
/// of such noise than of white noise) is still told right.
#[test]
fn a_slow_sine_is_no_stick_slip_and_band_limited_noise_is_still_a_floor() {
    let dir = scratch("not-told-sine");
    let mut noise = Noise(0x5851_f42d_4c95_7f2d);
    let fs = 6400.0;
    let mut csv = String::from("t_s,disc_x,pad_x\n");
    for i in 0..(3.0 * fs) as usize {
        let t = i as f64 / fs;
        let pad = 8.0 * (std::f64::consts::TAU * 3.0 * t).sin() + noise.gauss(0.02);
        csv += &format!("{t:.9},{:.6},{pad:.6}\n", noise.gauss(0.02));
    }
    let v = analyze(&dir, "sine.csv", &csv);
    undecided(&v);
    let floor = v["estimator"]["floor_note"].as_str().unwrap_or("");
    assert!(floor.contains("straight lines"), "{floor}");

    // the control: stick-slip at 50 Hz, stick fraction 0.5, noise through a 2-pole Butterworth
    // low-pass at 2 kHz on each channel, sampled at 51.2 kHz
    let fs = 51_200.0;
    let w = (std::f64::consts::PI * 2000.0 / fs).tan();
    let d = 1.0 + std::f64::consts::SQRT_2 * w + w * w;
    let (k, a1, a2) = (w * w / d, 2.0 * (w * w - 1.0) / d, (1.0 - std::f64::consts::SQRT_2 * w + w * w) / d);
    let mut lp = [[0.0f64; 4]; 4];
    // white noise of 0.3 m/s^2 through the low-pass: about 0.05 m/s^2
    let (csv, truth) = stick_slip_with(fs, 1.0, 50.0, 0.5, 10.0, 0.0, |c| {
        let x = noise.gauss(0.3);
        let s = &mut lp[c];
        let y = k * x + 2.0 * k * s[0] + k * s[1] - a1 * s[2] - a2 * s[3];
        *s = [x, s[0], y, s[2]];
        y
    });
    told(&analyze(&dir, "band_limited.csv", &csv), truth);
}
