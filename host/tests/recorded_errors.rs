//! Bad recordings: each gets exit code 2 and one line on stderr naming the file, the line (as
//! counted by hand in the text below: line 1 is the first line of the file) and the column or
//! rule; never a panic.

mod recorded_common;

use recorded_common::*;

const HEADER: &str = "t;disc_x;pad_x;pad_trail;pad_lead\n";

/// `rows` uniform rows at 2 kHz (t printed with 4 decimals), decimal commas.
fn rows(from: usize, to: usize) -> String {
    (from..to).map(|i| format!("{};0,1;-0,2;0,3;0,4\n", format!("{:.4}", i as f64 / 2000.0).replace('.', ","))).collect()
}

fn file(name: &str, text: &str) -> String {
    write(&scratch(&format!("errors-{name}")), "rec.csv", text)
}

#[test]
fn a_missing_column_names_it_and_the_header_line() {
    // pad_x is the one channel an analysis needs (issue 32: the others may be absent)
    let f = file("missing", "t;disc_x;pad_trail;pad_lead\n0;1;2;3\n");
    bad(&["analyze", &f], &[&f, "line 1", "no pad_x", "pad_x is needed"]);
    let f = file("missing-time", "disc_x,pad_x,pad_trail,pad_lead\n1,2,3,4\n");
    bad(&["analyze", &f], &[&f, "line 1", "time"]);
}

#[test]
fn a_non_numeric_cell() {
    // header line 1, data lines 2, 3, 4: line 4 holds the bad cell
    let mut t = format!("{HEADER}{}", rows(0, 2));
    t.push_str("0,0010;0,1;abc;0,3;0,4\n");
    t.push_str(&rows(3, 10));
    let f = file("nonnumeric", &t);
    bad(&["analyze", &f], &[&f, "line 4", "column 3", "`pad_x`", "`abc` is not a number"]);
}

#[test]
fn an_empty_cell() {
    let t = format!("{HEADER}{}0,0010;0,1;0,2;;0,4\n", rows(0, 2));
    let f = file("emptycell", &t);
    bad(&["analyze", &f], &[&f, "line 4", "`pad_trail`", "empty cell"]);
}

#[test]
fn a_decimal_comma_in_a_comma_separated_file() {
    let f = file("comma", "t,disc_x,pad_x,pad_trail,pad_lead\n0,1,2,3,4\n\"0,0005\",1,2,3,4\n");
    bad(&["analyze", &f], &[&f, "line 3", "column 1", "not a number", "semicolon"]);
}

#[test]
fn a_ragged_row() {
    let t = format!("{HEADER}{}0,0020;0,1;0,2;0,3\n{}", rows(0, 4), rows(5, 8));
    let f = file("ragged", &t);
    bad(&["analyze", &f], &[&f, "line 6", "4 fields", "has 5", "ragged"]);
    let t = format!("{HEADER}{}0,0020;0,1;0,2;0,3;0,4;9\n", rows(0, 4));
    let f = file("ragged-long", &t);
    bad(&["analyze", &f], &[&f, "line 6", "6 fields"]);
}

#[test]
fn a_time_column_that_does_not_increase() {
    // rows 0..5 on lines 2..6; line 7 repeats the time of line 6
    let t = format!("{HEADER}{}0,0020;0,1;0,2;0,3;0,4\n{}", rows(0, 5), rows(6, 9));
    let f = file("repeat", &t);
    bad(&["analyze", &f], &[&f, "line 7", "increase strictly"]);
    let t = format!("{HEADER}{}0,0001;0,1;0,2;0,3;0,4\n", rows(0, 5));
    let f = file("backwards", &t);
    bad(&["analyze", &f], &[&f, "line 7", "does not come after"]);
}

#[test]
fn a_gap_in_the_time_column() {
    // rows 0..6 on lines 2..7, then row 8 (row 7 missing) on line 8: interval 2 dt
    let t = format!("{HEADER}{}{}", rows(0, 6), rows(7, 12));
    let f = file("gap", &t);
    bad(&["analyze", &f], &[&f, "line 8", "uniformly sampled"]);
}

#[test]
fn an_empty_file_and_a_header_alone() {
    let f = file("empty", "");
    bad(&["analyze", &f], &[&f, "empty file"]);
    let f = file("blank", "\n\n  \n");
    bad(&["analyze", &f], &[&f, "empty file"]);
    let f = file("header", HEADER);
    bad(&["analyze", &f], &[&f, "line 1", "no data rows"]);
    let f = file("header-blank", &format!("\n{HEADER};;;;\n\n"));
    bad(&["analyze", &f], &[&f, "line 2", "no data rows"]);
    let f = file("one-row", &format!("{HEADER}{}", rows(0, 1)));
    bad(&["analyze", &f], &[&f, "line 2", "single data row"]);
}

#[test]
fn a_bad_unit_and_a_low_rate() {
    let f = file("unit", "t [s];disc_x [V];pad_x;pad_trail;pad_lead\n0;1;2;3;4\n");
    bad(&["analyze", &f], &[&f, "line 1", "`disc_x [V]`", "unit `v`"]);
    // 500 Hz: below the groan band's 1000 Hz
    let t: String = (0..100).map(|i| format!("{},0,0,0,0\n", i as f64 / 500.0)).collect();
    let f = file("slow", &format!("t,disc_x,pad_x,pad_trail,pad_lead\n{t}"));
    bad(&["analyze", &f], &[&f, "lines 2 to 101", "sample rate 500", "1000 Hz"]);
}

#[test]
fn line_numbers_count_the_preamble_and_crlf() {
    let mut t = String::from("Exported by a logger\r\nchannels: 4\r\n\r\n");
    t.push_str(&HEADER.replace('\n', "\r\n")); // line 4
    t.push_str(&rows(0, 3).replace('\n', "\r\n")); // lines 5, 6, 7
    t.push_str("0,0015;x;0;0;0\r\n"); // line 8
    let f = file("preamble", &t);
    bad(&["analyze", &f], &[&f, "line 8", "`disc_x`", "`x`"]);
}

#[test]
fn options_and_files_that_do_not_exist() {
    bad(&["analyze", "/nonexistent/rec.csv"], &["/nonexistent/rec.csv", "cannot open"]);
    let f = file("from", &format!("{HEADER}{}", rows(0, 10)));
    bad(&["analyze", &f, "--from", "5"], &["--from 5", "line 11"]);
    bad(&["analyze", &f, "--segment", "7"], &["--segment 7"]);
    bad(&["analyze", &f, "--breakaway-jump", "-1"], &["--breakaway-jump -1"]);
    bad(&["compare", "push_center", "/nonexistent/rec.csv"], &["/nonexistent/rec.csv"]);
    bad(&["sil", "push_center", "--noise", "-1"], &["--noise -1"]);
    // mu_s = mu_k: no breakaway jump for the estimator's thresholds, and no clamped phase to
    // measure a floor in (with one, the floor sets them)
    bad(&["sil", "thesis-mu", "--quiet-lead", "0"], &["thesis-mu", "not positive", "--breakaway-jump"]);
    bad(&["analyze", &f, "--scene", "thesis-mu"], &["thesis-mu", "--breakaway-jump"]);
}

#[test]
fn a_channel_mapped_to_the_time_column_is_named_as_such() {
    let dir = scratch("channel-on-time");
    let f = write(&dir, "rec.csv", "time,acc\n0,1\n0.001,2\n0.002,3\n");
    bad(&["analyze", &f, "--channel", "pad_x=time"], &["rec.csv", "line 1", "--channel names the time column `time`"]);
}
