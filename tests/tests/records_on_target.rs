//! The firmware's log, end to end: the on-target program `records` (tests/on-target) plays a rig
//! session through the firmware's rig (`sample_words`) and `Logbook` on the emulated Cortex-M4F and
//! writes every record with the firmware's defmt formatting over semihosting; this test runs
//! it under QEMU, decodes the captured stream with the host's `stickslip decode` code and the
//! program's ELF, and compares every decoded record with the same session played on x86-64
//! (the same sources, included below), field by field:
//!
//! - nothing lost: every frame decodes, no byte skipped, no incomplete frame;
//! - the same records in the same order, with the level and the timestamp each should have;
//! - every field under its documented key (firmware/README.md, "Log records", written out
//!   again below, not taken from the formatting code), in order, with its value: integers,
//!   strings and booleans equal, f32 values bit for bit (defmt prints them shortest, they read
//!   back to the same f32), the arrays of the window record element by element.
//!
//! The stack figures of the `start` record exist only on the target: checked for plausibility.
//!
//! Ignored by default: it needs qemu-system-arm and the cross-built ELF. `scripts/test-all.sh`
//! runs
//!
//!     STICKSLIP_ON_TARGET_RECORDS_ELF=tests/on-target/target/thumbv7em-none-eabihf/release/records \
//!     STICKSLIP_ON_TARGET_RECORDS_STREAM=<where to keep the captured stream> \
//!         cargo test --release -p stickslip-crosscheck --test records_on_target -- --ignored
//!
//! and then `stickslip decode` on the kept stream. Without the ELF's variable it fails.

use serde_json::Value;
use stickslip::recorded::decode::{decode_stream, load_table, Record as Decoded};
use stickslip_model::rig::contact::ContactEventKind;
use stickslip_model::rig::sequencer::{Command, CommandResult, FaultCause, SeqState, Valves};
use stickslip_model::Halt;

mod qemu;

// The log session the on-target program plays and the firmware's log records (tests/cases),
// built for the host: the same code the Cortex-M4F runs.
use stickslip_crosscheck_cases::{logbook, records_session};
use stickslip_model::rig::pipeline::{Rig, RigConfig};

use logbook::{Record, RecordSink};
use records_session::{uptime_us, SessionOut};

/// An expected field value.
#[derive(Clone, Debug)]
enum V {
    U(u64),
    F32(f32),
    F64(f64),
    S(String),
    B(bool),
    F32s(Vec<f32>),
    /// A figure only the target has (the stack): a non-negative integer, not compared.
    TargetOnly,
}

/// An expected record.
#[derive(Clone, Debug)]
struct Expected {
    timestamp_us: u64,
    level: &'static str,
    kind: &'static str,
    fields: Vec<(&'static str, V)>,
}

// The names the log uses (firmware/README.md, "Log records").

fn state(s: SeqState) -> V {
    V::S(
        match s {
            SeqState::Idle => "idle",
            SeqState::Clamp => "clamp",
            SeqState::Drive => "drive",
            SeqState::Record => "record",
            SeqState::Vent => "vent",
            SeqState::Fault(_) => "fault",
        }
        .into(),
    )
}

fn fault(c: FaultCause) -> &'static str {
    match c {
        FaultCause::EStop => "estop",
        FaultCause::NonFinite => "non_finite",
        FaultCause::ActuatorPressure => "actuator_pressure",
        FaultCause::BandPressure => "band_pressure",
        FaultCause::AccelSaturation => "accel_saturation",
        FaultCause::ClampTimeout => "clamp_timeout",
        FaultCause::DriveTimeout => "drive_timeout",
        FaultCause::RecordTimeout => "record_timeout",
    }
}

fn cause(s: SeqState) -> V {
    V::S(if let SeqState::Fault(c) = s { fault(c) } else { "none" }.into())
}

fn valves(v: Valves) -> V {
    V::U(u64::from(v.actuator_open) + 2 * u64::from(v.band_open))
}

fn s(x: &str) -> V {
    V::S(x.to_string())
}

fn expected(timestamp_us: u64, r: &Record<'_>) -> Expected {
    type Fields = Vec<(&'static str, V)>;
    let (level, kind, fields): (&'static str, &'static str, Fields) = match *r {
        Record::Boot(b) => (
            "info",
            "boot",
            vec![
                ("fw", s(b.fw)),
                ("schema", V::U(2)),
                ("reset", s(b.reset.name())),
                ("sysclk_hz", V::U(b.sysclk_hz.into())),
                ("fs_hz", V::F32(b.fs_hz)),
                ("timer_clocks", V::U(b.timer_clocks.into())),
                ("adc_channels", V::U(b.adc_channels.into())),
                ("window_samples", V::U(b.window_samples.into())),
                ("batch_frames", V::U(b.batch_frames.into())),
                ("pressure", V::B(b.pressure)),
                ("end_of_stroke", V::B(b.end_of_stroke)),
                ("oversample", V::U(b.oversample.into())),
            ],
        ),
        Record::Armed { build_us, caliper, beta_m, f_n_n, v_m_s, n0_n } => (
            "info",
            "armed",
            vec![
                ("build_us", V::U(build_us.into())),
                ("caliper", s(caliper)),
                ("beta", V::F32(beta_m)),
                ("f_n", V::F32(f_n_n)),
                ("v", V::F32(v_m_s)),
                ("n0", V::F32(n0_n)),
            ],
        ),
        Record::ConfigError { field, rule, value } => {
            ("error", "config_error", vec![("field", s(field)), ("rule", s(rule)), ("value", V::F64(value))])
        }
        Record::Start { watchdog_us, .. } => (
            "info",
            "start",
            vec![("watchdog_us", V::U(watchdog_us.into())), ("stack_used", V::TargetOnly), ("stack_size", V::TargetOnly)],
        ),
        Record::State { n, record, from, to, valves: v } => (
            "info",
            "state",
            vec![
                ("n", V::U(n)),
                ("rec", V::U(record.into())),
                ("from", state(from)),
                ("to", state(to)),
                ("cause", cause(to)),
                ("valves", valves(v)),
            ],
        ),
        Record::Command { n, state: st, command, result } => (
            "info",
            "command",
            vec![
                ("n", V::U(n)),
                ("in", state(st)),
                (
                    "cmd",
                    s(match command {
                        Command::Start => "start",
                        Command::Stop => "stop",
                        Command::Reset => "reset",
                    }),
                ),
                (
                    "result",
                    s(match result {
                        CommandResult::Accepted => "accepted",
                        CommandResult::Ignored => "ignored",
                        CommandResult::Refused(_) => "refused",
                    }),
                ),
                ("refused_by", s(if let CommandResult::Refused(c) = result { fault(c) } else { "none" })),
            ],
        ),
        Record::Event { n, record, event, v_r_m_s, a_rel_m_s2 } => (
            "info",
            "event",
            vec![
                ("n", V::U(n)),
                ("rec", V::U(record.into())),
                ("sample", V::U(event.sample)),
                (
                    "kind",
                    s(match event.kind {
                        ContactEventKind::StickToSlip => "stick_to_slip",
                        ContactEventKind::SlipToStick => "slip_to_stick",
                        ContactEventKind::Reversal => "reversal",
                    }),
                ),
                ("v_r", V::F32(v_r_m_s)),
                ("a_rel", V::F32(a_rel_m_s2)),
            ],
        ),
        Record::Window { window: w, extras: x } => {
            let r = &w.report;
            let m = r.model.unwrap_or_default();
            (
                "info",
                "window",
                vec![
                    ("n", V::U(x.n)),
                    ("rec", V::U(w.record.into())),
                    ("idx", V::U(r.index.into())),
                    ("first", V::U(r.first_sample)),
                    ("samples", V::U(r.samples.into())),
                    ("valid", V::U(r.valid_samples.into())),
                    ("pp", V::F32s(r.pp_m_s2.to_vec())),
                    ("rms", V::F32s(r.rms_m_s2.to_vec())),
                    ("groan_rms", V::F32s(r.groan_rms_m_s2.to_vec())),
                    ("stick", V::F32(r.stick_fraction)),
                    ("ss_hz", V::F32(r.stick_slip_hz)),
                    ("onsets", V::U(r.slip_onsets.into())),
                    ("saturated", V::U(r.saturated_samples.into())),
                    ("faulted", V::U(r.faulted_samples.into())),
                    ("nonfinite", V::B(r.non_finite)),
                    ("model", V::B(r.model.is_some())),
                    ("model_samples", V::U(m.samples.into())),
                    ("model_stick", V::F32(m.stick_fraction)),
                    ("model_ss_hz", V::F32(m.stick_slip_hz)),
                    ("model_onsets", V::U(m.slip_onsets.into())),
                    ("residual_rms", V::F32(m.residual_rms_m_s2)),
                    (
                        "model_halt",
                        s(match m.halt {
                            None => "none",
                            Some(Halt::NonFinite { .. }) => "non_finite",
                            Some(Halt::Diverged { .. }) => "diverged",
                            Some(Halt::ContactLoss { .. }) => "contact_loss",
                            Some(Halt::TransitionStorm { .. }) => "transition_storm",
                        }),
                    ),
                    ("p_mean", V::F32s(w.pressure.mean_bar.to_vec())),
                    ("p_min", V::F32s(w.pressure.min_bar.to_vec())),
                    ("p_max", V::F32s(w.pressure.max_bar.to_vec())),
                    ("state", state(x.state)),
                    ("overruns", V::U(x.overruns.into())),
                    ("events_dropped", V::U(x.events_dropped.into())),
                    ("windows_dropped", V::U(x.windows_dropped.into())),
                    ("batch_cyc_max", V::U(x.batch_cycles_max.into())),
                    ("batch_cyc_budget", V::U(x.batch_cycles_budget.into())),
                ],
            )
        }
        Record::Floor { n, record, floor: f, onset_m_s2, stick_m_s2 } => (
            "info",
            "floor",
            vec![
                ("n", V::U(n)),
                ("rec", V::U(record.into())),
                ("samples", V::U(f.samples.into())),
                ("mean", V::F32s(f.mean_m_s2.to_vec())),
                ("sigma", V::F32s(f.sigma_m_s2.to_vec())),
                ("pp", V::F32s(f.pp_m_s2.to_vec())),
                ("onset", V::F32(onset_m_s2)),
                ("stick", V::F32(stick_m_s2)),
            ],
        ),
        Record::Health { n, record, index, flat, noisy, undecided } => (
            "warn",
            "health",
            vec![
                ("n", V::U(n)),
                ("rec", V::U(record.into())),
                ("idx", V::U(index.into())),
                ("flat", V::U(flat.into())),
                ("noisy", V::U(noisy.into())),
                ("undecided", V::B(undecided)),
            ],
        ),
        Record::Overrun { n, count } => ("warn", "overrun", vec![("n", V::U(n)), ("count", V::U(count.into()))]),
        Record::Stall { n, ms, adc_ovr } => {
            ("error", "stall", vec![("n", V::U(n)), ("ms", V::U(ms.into())), ("adc_ovr", V::B(adc_ovr))])
        }
        Record::Input { name, active } => ("warn", "input", vec![("name", s(name)), ("active", V::B(active))]),
        Record::Panic { file, line, msg } => {
            ("error", "panic", vec![("file", s(file)), ("line", V::U(line.into())), ("msg", s(msg))])
        }
    };
    Expected { timestamp_us, level, kind, fields }
}

/// Collects the session's records as expected values.
#[derive(Default)]
struct Collect {
    now_us: u64,
    records: Vec<Expected>,
}

impl RecordSink for Collect {
    fn record(&mut self, r: &Record<'_>) {
        self.records.push(expected(self.now_us, r));
    }
}

impl SessionOut for Collect {
    fn at_frame(&mut self, frames: u64) {
        self.now_us = uptime_us(frames);
    }
}

/// The session on x86-64.
fn host_session() -> Vec<Expected> {
    let mut c = Collect::default();
    let summary = records_session::run(&mut c, || (0, 0)).expect("the session runs on the host");
    assert_eq!(summary.records as usize, c.records.len());
    c.records
}

fn f32_of(v: &Value, what: &str) -> f32 {
    v.as_f64().unwrap_or_else(|| panic!("{what}: {v} is not a number")) as f32
}

/// Compares one decoded record with its expected value; the error names the record and field.
fn compare(i: usize, got: &Decoded, want: &Expected) -> Result<(), String> {
    let at = format!("record {i} ({} at frame {})", want.kind, got.frame);
    if got.kind != want.kind {
        return Err(format!("{at}: kind {:?}, message {:?}", got.kind, got.message));
    }
    if got.level != Some(want.level) {
        return Err(format!("{at}: level {:?}, expected {}", got.level, want.level));
    }
    let ts = got.timestamp_s.ok_or_else(|| format!("{at}: no timestamp"))?;
    if (ts * 1e6).round() as u64 != want.timestamp_us {
        return Err(format!("{at}: timestamp {ts} s, expected {} us", want.timestamp_us));
    }
    let keys: Vec<&str> = got.fields.iter().map(|(k, _)| k.as_str()).collect();
    let want_keys: Vec<&str> = want.fields.iter().map(|(k, _)| *k).collect();
    if keys != want_keys {
        return Err(format!("{at}: keys {keys:?}, expected {want_keys:?}"));
    }
    for ((k, g), (_, w)) in got.fields.iter().zip(&want.fields) {
        let what = format!("{at} field {k}");
        let ok = match w {
            V::U(x) => g.as_u64() == Some(*x),
            V::F32(x) => f32_of(g, &what).to_bits() == x.to_bits(),
            V::F64(x) => g.as_f64().map(f64::to_bits) == Some(x.to_bits()),
            V::S(x) => g.as_str() == Some(x.as_str()),
            V::B(x) => g.as_bool() == Some(*x),
            V::F32s(xs) => g.as_array().is_some_and(|a| {
                a.len() == xs.len() && a.iter().zip(xs).all(|(v, x)| f32_of(v, &what).to_bits() == x.to_bits())
            }),
            V::TargetOnly => g.as_u64().is_some(),
        };
        if !ok {
            return Err(format!("{what}: decoded {g}, expected {w:?}"));
        }
    }
    Ok(())
}

#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_RECORDS_ELF (scripts/test-all.sh runs it)"]
fn the_firmware_log_decodes_to_the_records_the_host_computes() {
    let elf = qemu::elf_from_env("STICKSLIP_ON_TARGET_RECORDS_ELF", "records");
    let (status, stream, err) = qemu::run(&elf);
    assert!(status.success(), "QEMU: {status}; stderr: {err}");
    if let Some(keep) = std::env::var_os("STICKSLIP_ON_TARGET_RECORDS_STREAM") {
        std::fs::write(&keep, &stream).unwrap_or_else(|e| panic!("cannot keep the stream in {keep:?}: {e}"));
    }

    let table = load_table("records ELF", &std::fs::read(&elf).expect("the ELF reads")).expect("the ELF has a defmt table");
    let mut decoded = Vec::new();
    let st = decode_stream(&table, stream.as_slice(), |r| decoded.push(r)).expect("the stream reads");
    println!("records: {} bytes; {}", stream.len(), st.summary());
    assert_eq!(st.bytes as usize, stream.len());
    assert_eq!((st.frames_dropped, st.bytes_skipped, st.incomplete_bytes), (0, 0, 0), "frames lost: {}", st.summary());

    let want = host_session();
    for (i, (g, w)) in decoded.iter().zip(&want).enumerate() {
        if let Err(e) = compare(i, g, w) {
            panic!("{e}\n  decoded message: {}", g.message);
        }
    }
    assert_eq!(decoded.len(), want.len(), "records decoded vs records of the session on the host");

    // What the session must have produced for this to test the contract (not the values,
    // which the comparison above holds): every record kind it can make.
    let count = |k: &str| want.iter().filter(|e| e.kind == k).count();
    for (k, n) in [("boot", 2), ("config_error", 1), ("armed", 1), ("start", 1), ("overrun", 1), ("input", 2)] {
        assert_eq!(count(k), n, "{k} records");
    }
    assert!(count("window") >= 4, "windows: {}", count("window"));
    assert_eq!(count("floor"), 1, "floor records");
    assert!(count("health") >= 1, "health records: {}", count("health"));
    assert!(count("event") >= 20, "events: {}", count("event"));
    assert!(count("command") >= 2 && count("state") >= 5, "commands {} states {}", count("command"), count("state"));
    let kinds: Vec<&str> = want.iter().filter(|e| e.kind == "state").map(|e| match &e.fields[3].1 {
        V::S(s) => s.as_str(),
        _ => "",
    }).collect();
    assert!(kinds.contains(&"record") && kinds.contains(&"fault") && kinds.contains(&"idle"), "states entered: {kinds:?}");
}

/// `stickslip record` on the same program's stream as QEMU produces it: the stream is fed to
/// record's pipeline (`record_reader`, what `record --input -` runs) while the program runs,
/// through a copy kept here. The raw file must be the bytes QEMU wrote, each KIND.csv what
/// `stickslip decode --kind KIND` prints for the raw file, nothing lost, and the kinds and
/// record counts those of the session on the host.
#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_RECORDS_ELF (scripts/test-all.sh runs it)"]
fn record_writes_what_decode_reads_from_the_stream_as_it_is_produced() {
    use std::io::Read;
    use std::sync::{Arc, Mutex};
    use stickslip::recorded::decode::{run as decode_run, DecodeRequest};
    use stickslip::recorded::live::{record_reader, source::End};

    /// QEMU's stdout, copied as it is read.
    struct Copy<R> {
        inner: R,
        kept: Arc<Mutex<Vec<u8>>>,
    }
    impl<R: Read> Read for Copy<R> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = self.inner.read(buf)?;
            self.kept.lock().unwrap().extend_from_slice(&buf[..n]);
            Ok(n)
        }
    }

    let elf = qemu::elf_from_env("STICKSLIP_ON_TARGET_RECORDS_ELF", "records");
    let (mut child, stdout) = qemu::spawn(&elf);
    let kept = Arc::new(Mutex::new(Vec::new()));
    let out = std::env::temp_dir().join(format!("stickslip-record-on-target-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let table = load_table("records ELF", &std::fs::read(&elf).expect("the ELF reads")).expect("the ELF has a defmt table");
    let waiter = std::thread::spawn(move || qemu::wait(&mut child));
    let rec = record_reader(&table, Copy { inner: stdout, kept: kept.clone() }, Some(&out), None, &mut std::io::sink())
        .expect("record's folder");
    let status = waiter.join().expect("QEMU's waiter");
    assert!(status.success(), "QEMU: {status}");
    println!("record: {}", rec.summary());
    assert_eq!(rec.end, End::Input);
    let stream = kept.lock().unwrap().clone();
    let raw = std::fs::read(&rec.raw_path).expect("raw.defmt");
    assert!(raw == stream, "raw.defmt ({} bytes) is not QEMU's stream ({} bytes)", raw.len(), stream.len());
    assert_eq!((rec.stats.bytes as usize, rec.stats.frames_dropped, rec.stats.bytes_skipped, rec.stats.incomplete_bytes), (stream.len(), 0, 0, 0));

    let want = host_session();
    let mut kinds: Vec<&str> = Vec::new();
    for e in &want {
        if !kinds.contains(&e.kind) {
            kinds.push(e.kind);
        }
    }
    let got: Vec<(&str, u64)> = rec.kinds.iter().map(|k| (k.kind.as_str(), k.rows)).collect();
    let expect: Vec<(&str, u64)> = kinds.iter().map(|k| (*k, want.iter().filter(|e| e.kind == *k).count() as u64)).collect();
    assert_eq!(got, expect, "kinds and records per kind, recorded vs the session on the host");
    let raw_path = rec.raw_path.to_str().expect("a UTF-8 path").to_string();
    for k in &kinds {
        let ours = std::fs::read_to_string(out.join(format!("{k}.csv"))).expect("the kind's CSV");
        let theirs = decode_run(&DecodeRequest { elf: &elf, input: &raw_path, json: false, kind: Some(k) }).expect("decode --kind");
        assert!(ours == theirs, "{k}.csv differs from decode --kind {k}");
    }
    assert_eq!(rec.firmware.windows as usize, want.iter().filter(|e| e.kind == "window").count());
    let _ = std::fs::remove_dir_all(&out);
}

/// The host side of the comparison on its own, runnable without QEMU: the session plays, and
/// its records satisfy what the schema says of them (so the comparison above cannot pass on an
/// empty or degenerate session).
#[test]
fn the_session_makes_every_record_the_schema_needs() {
    let recs = host_session();
    let kinds: Vec<&str> = recs.iter().map(|r| r.kind).collect();
    assert_eq!(&kinds[..5], ["boot", "config_error", "boot", "armed", "start"]);
    // the refused configuration names the field
    assert!(matches!(&recs[1].fields[0].1, V::S(f) if f == "beta"), "{:?}", recs[1].fields);
    // the floor: 6 batches of the clamp (the first sample of Clamp is its entering tick),
    // a_rel's onset from its sigma (6 sigma of two channels of 0.5 m/s^2 noise: about 4 m/s^2)
    let floor = recs.iter().find(|r| r.kind == "floor").expect("a floor record");
    let fget = |k: &str| floor.fields.iter().find(|(n, _)| *n == k).map(|(_, v)| v.clone()).unwrap();
    assert!(matches!(fget("samples"), V::U(n) if (256..=384).contains(&n)), "{:?}", fget("samples"));
    match (fget("sigma"), fget("onset")) {
        (V::F32s(sig), V::F32(onset)) => {
            assert!(sig[..4].iter().all(|s| (0.35..0.65).contains(s)), "sigmas {sig:?}");
            assert!((onset - 6.0 * sig[4]).abs() <= 1e-4 * onset, "onset {onset} vs 6 sigma {}", 6.0 * sig[4]);
        }
        other => panic!("floor fields {other:?}"),
    }
    // the dead trailing-edge sensor, and only it, is reported flat after every record window;
    // it does not stop the contact decision
    for h in recs.iter().filter(|r| r.kind == "health") {
        let hget = |k: &str| h.fields.iter().find(|(n, _)| *n == k).map(|(_, v)| v.clone()).unwrap();
        assert!(matches!(hget("flat"), V::U(4)), "{:?}", h.fields);
        assert!(matches!(hget("noisy"), V::U(4)), "a flat channel has no signal either: {:?}", h.fields);
        assert!(matches!(hget("undecided"), V::B(false)), "{:?}", h.fields);
    }
    // timestamps never go back
    assert!(recs.windows(2).all(|w| w[0].timestamp_us <= w[1].timestamp_us));
    // each window's events: logged ones plus dropped ones (the limit is never reached here)
    let windows: Vec<&Expected> = recs.iter().filter(|r| r.kind == "window").collect();
    assert!(windows.len() >= 4);
    for w in &windows {
        let get = |k: &str| w.fields.iter().find(|(n, _)| *n == k).map(|(_, v)| v.clone()).unwrap();
        assert!(matches!(get("events_dropped"), V::U(0)));
        // 0.1 s at the firmware's rate: 84 MHz / (820 x 4) = 25 609.76 Hz, 2 561 samples
        assert!(matches!(get("samples"), V::U(2561)), "{:?}", get("samples"));
        // the overrun shows in every window after it
        if let (V::U(n), V::U(o)) = (get("n"), get("overruns")) {
            let expect = u64::from(n > 100 * 64);
            assert_eq!(o, expect, "window at frame {n}");
        }
    }
}

/// The firmware's decimation (`Rig::frame`): four scans of distinct words summed channel by
/// channel, with and without the pressure channels (then 0 bar's count, times four), against
/// sums taken here.
#[test]
fn the_decimation_sums_the_scans_of_a_frame() {
    use stickslip_model::rig::{ACCEL_CHANNELS, CHANNELS};
    for has_pressure in [true, false] {
        let mut cfg = RigConfig::rig(25_600.0, has_pressure, true);
        cfg.calibration.adc.oversample = 4;
        let rig = Rig::new(&cfg).expect("the rig's configuration");
        let ch = cfg.adc_channels();
        assert_eq!(cfg.frame_words(), 4 * ch);
        let words: Vec<u16> = (0..4 * ch).map(|i| (1000 + 37 * i * i % 3000) as u16).collect();
        let f = rig.frame(&words);
        for c in 0..ch {
            let want: u32 = (0..4).map(|k| words[k * ch + c] as u32).sum();
            assert_eq!(f.counts[c] as u32, want, "channel {c}, pressure {has_pressure}");
        }
        if !has_pressure {
            let p = &cfg.calibration.pressure;
            for j in 0..2 {
                let zero = 4 * p[j].count_for(&cfg.calibration.adc, 0.0) as u32;
                assert_eq!(f.counts[ACCEL_CHANNELS + j] as u32, zero, "pressure channel {j} at 0 bar");
            }
        }
        // the calibration of the sum reads what one scan of the same counts reads
        let cal = stickslip_model::rig::calibration::Calibrator::new(&cfg.calibration).unwrap();
        let one = stickslip_model::rig::calibration::Calibrator::new(&RigConfig::rig(25_600.0, true, true).calibration).unwrap();
        let scan: [u16; CHANNELS] = [2100, 1990, 2048, 3000, 900, 1500];
        let frame4 = stickslip_model::rig::calibration::Frame { counts: scan.map(|c| 4 * c) };
        let frame1 = stickslip_model::rig::calibration::Frame { counts: scan };
        let (a4, a1) = (cal.calibrate(&frame4), one.calibrate(&frame1));
        for c in 0..ACCEL_CHANNELS {
            assert!((a4.accel_m_s2[c] - a1.accel_m_s2[c]).abs() <= 1e-5 * a1.accel_m_s2[c].abs().max(1.0), "channel {c}");
        }
    }
}
