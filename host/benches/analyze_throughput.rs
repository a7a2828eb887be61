//! Throughput and peak memory of `stickslip analyze` on a long recording (a benchmark, not a
//! test: it asserts nothing).
//!
//! Generates a recording at 25.6 kHz x 4 channels as a spreadsheet would export it (semicolons,
//! decimal commas, time to 0.1 us, accelerations to 0.1 mm/s^2: about 50 bytes a row) into a
//! temporary file, runs the release binary on it under `/usr/bin/time -v`, and prints the
//! file size, the wall time, the throughput [MB/s, 1 MB = 1e6 bytes] and the peak resident
//! memory [MB]. Targets (issue 5): >= 50 MB/s, < 100 MB resident.
//!
//!     cargo bench -p stickslip --bench analyze_throughput                 # 5 minutes of signal
//!     STICKSLIP_BENCH_SECONDS=3600 cargo bench -p stickslip --bench analyze_throughput   # 1 hour
//!
//! STICKSLIP_BENCH_DIR sets the directory of the temporary file (default: the system's temp
//! directory); the file is deleted afterwards unless STICKSLIP_BENCH_KEEP is set.

use std::io::{BufWriter, Write};
use std::process::Command;
use std::time::Instant;

const FS: f64 = stickslip_model::design::SAMPLE_RATE_HZ;

/// Appends `v` (an integer number of 10^-`decimals` units) as a decimal with a comma.
fn put_fixed(out: &mut Vec<u8>, v: i64, decimals: u32) {
    if v < 0 {
        out.push(b'-');
    }
    let a = v.unsigned_abs();
    let p = 10u64.pow(decimals);
    let (int, frac) = (a / p, a % p);
    out.extend_from_slice(int.to_string().as_bytes());
    out.push(b',');
    let f = frac.to_string();
    for _ in f.len()..decimals as usize {
        out.push(b'0');
    }
    out.extend_from_slice(f.as_bytes());
}

fn generate(path: &std::path::Path, rows: u64) -> std::io::Result<u64> {
    let mut w = BufWriter::with_capacity(1 << 20, std::fs::File::create(path)?);
    w.write_all(b"\"Time [s]\";\"disc_x [m/s^2]\";\"pad_x [m/s^2]\";\"pad_trail [m/s^2]\";\"pad_lead [m/s^2]\"\r\n")?;
    let mut line = Vec::with_capacity(128);
    let mut rng: u32 = 0x1234_5678;
    let tau = 2.0 * std::f64::consts::PI;
    for i in 0..rows {
        line.clear();
        // t = i / 25600 s = i x 390.625 units of 0.1 us
        put_fixed(&mut line, (i as f64 * 390.625).round() as i64, 7);
        let t = i as f64 / FS;
        for (c, (amp, hz)) in [(0.8, 47.0), (20.0, 131.0), (6.0, 437.0), (35.0, 437.0)].iter().enumerate() {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            let noise = (rng >> 8) as f64 / (1u32 << 24) as f64 - 0.5;
            let v = amp * (tau * hz * t + c as f64).sin() + 0.3 * noise;
            line.push(b';');
            put_fixed(&mut line, (v * 1e4).round() as i64, 4);
        }
        line.extend_from_slice(b"\r\n");
        w.write_all(&line)?;
    }
    w.flush()?;
    Ok(std::fs::metadata(path)?.len())
}

fn main() {
    // `cargo bench` passes --bench; nothing else is accepted
    let seconds: f64 = std::env::var("STICKSLIP_BENCH_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(300.0);
    let rows = (seconds * FS).round() as u64;
    let dir = std::env::var_os("STICKSLIP_BENCH_DIR").map(std::path::PathBuf::from).unwrap_or_else(std::env::temp_dir);
    let path = dir.join(format!("stickslip-bench-{}s-{}.csv", seconds, std::process::id()));
    println!("generating {rows} rows ({seconds} s at 25.6 kHz) into {}", path.display());
    let t0 = Instant::now();
    let bytes = generate(&path, rows).expect("the recording can be written");
    println!("  {:.1} MB in {:.1} s", bytes as f64 / 1e6, t0.elapsed().as_secs_f64());

    let t1 = Instant::now();
    let out = Command::new("/usr/bin/time")
        .arg("-v")
        .arg(env!("CARGO_BIN_EXE_stickslip"))
        .args(["analyze", path.to_str().unwrap(), "--json"])
        .output()
        .expect("/usr/bin/time runs (Debian package `time`)");
    let wall = t1.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        eprintln!("analyze failed:\n{stderr}");
        std::process::exit(1);
    }
    let rss_kb: f64 = stderr
        .lines()
        .find_map(|l| l.trim().strip_prefix("Maximum resident set size (kbytes):"))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(f64::NAN);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let mbps = bytes as f64 / 1e6 / wall;
    println!("analyze: {} samples in {wall:.2} s", v["samples"]);
    println!("  throughput {mbps:.1} MB/s ({:.2} M rows/s)", rows as f64 / 1e6 / wall);
    println!("  peak resident memory {:.1} MB", rss_kb / 1024.0);
    println!(
        "  targets: >= 50 MB/s {}, < 100 MB {}",
        if mbps >= 50.0 { "met" } else { "MISSED" },
        if rss_kb / 1024.0 < 100.0 { "met" } else { "MISSED" }
    );
    println!("  pad_x pp {} m/s^2, peak {} Hz", v["channels"]["pad_x"]["pp"], v["channels"]["pad_x"]["peak_hz"]);
    if std::env::var_os("STICKSLIP_BENCH_KEEP").is_none() {
        let _ = std::fs::remove_file(&path);
    } else {
        println!("kept {}", path.display());
    }
}
