"""Writes the recording fixtures of host/tests/recorded_formats.rs with programs nobody on the
project wrote: pyuff (UFF dataset 58 ASCII and 58b double), Python's `wave` module (WAV, 16- and
24-bit PCM), numpy, a float32 58b written here from the published layout and read back with
pyuff as a check, and a float32 WAV written here from the RIFF layout. One synthetic
stick-slip record (4 channels, 25.6 kHz, 0.15 s): 100 Hz cycles, 40 % stick (pad_x = noise),
slips of one 167 Hz period and three of 500 Hz; every value an integer count k of 8 / 32768 m/s^2 (16-bit full scale 8 m/s^2), so CSV, WAV, 58b single and double hold
the same numbers exactly and the ASCII 58 (6 significant digits) to 5e-6.

    pip install pyuff numpy && python3 make.py      # in this directory
"""
import struct
import wave

import numpy as np
import pyuff

FS = 25600
N = 3840
FULL = 8.0  # m/s^2 at full scale
Q = FULL / 32768.0

rng = np.random.default_rng(32)
t = np.arange(N) / FS
phase = (t * 100.0) % 1.0
tau = (phase - 0.4) * 0.01  # s into the slip
# whole periods over the 6 ms slip: the relative velocity is back at 0 when it sticks again
burst = np.where(tau >= 0, 1.5 * np.sin(2 * np.pi * tau / 0.006) + 0.4 * np.sin(2 * np.pi * 500 * tau), 0.0)
noise = lambda: rng.normal(0.0, 0.01, N)
chans = {
    "disc_x": 0.2 * burst + noise(),
    "pad_x": burst + noise(),
    "pad_trail": 0.6 * burst + noise(),
    "pad_lead": -0.8 * burst + noise(),
}
counts = {k: np.clip(np.round(v / Q), -32768, 32767).astype(np.int16) for k, v in chans.items()}
vals = {k: c.astype(np.float64) * Q for k, c in counts.items()}
names = list(chans)

with open("rec.csv", "w") as f:
    f.write("t_s,disc_x,pad_x,pad_trail,pad_lead\n")
    for i in range(N):
        f.write(repr(i / FS) + "," + ",".join(repr(float(vals[k][i])) for k in names) + "\n")


def dset(name, binary, ord_type):
    return pyuff.prepare_58(
        binary=binary, id1=name, id2="stickslip fixture", id3="NONE", id4="NONE", id5="NONE",
        func_type=1, rsp_node=1, rsp_dir=1, ref_node=0, ref_dir=0, ord_data_type=ord_type,
        abscissa_spacing=1, abscissa_min=0.0, abscissa_inc=1.0 / FS, abscissa_spec_data_type=17,
        abscissa_axis_units_lab="s", ordinate_spec_data_type=12, ordinate_len_unit_exp=1,
        ordinate_axis_units_lab="m/s^2", orddenom_spec_data_type=0, z_axis_spec_data_type=0,
        data=vals[name], x=t,
    )


# order on disk differs from the CSV's: the reader must find them by name
order = ["pad_lead", "pad_x", "disc_x", "pad_trail"]
pyuff.UFF("rec_58.uff").write_sets([dset(n, 0, 2) for n in order], mode="overwrite", force_double=False)
# pyuff's binary writer reopens the file to append the values: with mode "overwrite" it
# truncates what it wrote; "add" to a new file works
import os
if os.path.exists("rec_58b_double.uff"):
    os.remove("rec_58b_double.uff")
pyuff.UFF("rec_58b_double.uff").write_sets([dset(n, 1, 4) for n in order], mode="add", force_double=True)

# float32 58b: pyuff writes doubles whatever the header says, so this one is written from
# the published layout (records 1-11 as pyuff writes them in the ASCII file above)
with open("rec_58.uff") as f:
    ascii_lines = f.read().split("\n")
out = bytearray()
i = 0
rec = 0
while i < len(ascii_lines):
    if ascii_lines[i].strip() == "-1" and i + 1 < len(ascii_lines) and ascii_lines[i + 1].strip().startswith("58"):
        header = ascii_lines[i + 2 : i + 13]
        name = order[rec]
        data = vals[name].astype("<f4").tobytes()
        out += b"    -1\n"
        out += ("    58b%6i%6i%12i%12i%6i%6i%12i%12i\n" % (1, 2, 11, len(data), 0, 0, 0, 0)).encode()
        out += ("\n".join(header) + "\n").encode()
        out += data
        out += b"    -1\n"
        rec += 1
        i += 13
    else:
        i += 1
open("rec_58b_single.uff", "wb").write(bytes(out))

# check: pyuff reads every file back to the values written
for fn, tol in [("rec_58.uff", 5e-6), ("rec_58b_double.uff", 0.0), ("rec_58b_single.uff", 0.0)]:
    sets = pyuff.UFF(fn).read_sets()
    assert len(sets) == 4, fn
    for s, name in zip(sets, order):
        err = np.max(np.abs(s["data"] - vals[name]) / np.maximum(np.abs(vals[name]), 1e-3))
        assert err <= tol, (fn, name, err)

with wave.open("rec.wav", "wb") as w:
    w.setnchannels(4)
    w.setsampwidth(2)
    w.setframerate(FS)
    # channel order in the WAV: pad_x, pad_trail, disc_x, pad_lead
    inter = np.stack([counts["pad_x"], counts["pad_trail"], counts["disc_x"], counts["pad_lead"]], axis=1)
    w.writeframes(inter.astype("<i2").tobytes())

# 24-bit PCM (Python's wave writes any sample width): the same counts, 8 bits up
with wave.open("rec24.wav", "wb") as w:
    w.setnchannels(4)
    w.setsampwidth(3)
    w.setframerate(FS)
    i32 = inter.astype("<i4") * 256
    b = i32.astype("<i4").tobytes()
    w.writeframes(b"".join(b[k : k + 3] for k in range(0, len(b), 4)))

# 32-bit float in m/s^2 (WAVE_FORMAT_IEEE_FLOAT, format tag 3), written from the RIFF layout:
# the values themselves, no SCALE needed
data = inter.astype("<f4") * np.float32(Q)
raw = data.astype("<f4").tobytes()
fmt = struct.pack("<HHIIHH", 3, 4, FS, FS * 16, 16, 32)
fact = struct.pack("<I", N)
body = b"WAVE" + b"fmt " + struct.pack("<I", len(fmt)) + fmt + b"fact" + struct.pack("<I", 4) + fact + b"data" + struct.pack("<I", len(raw)) + raw
open("rec_f32.wav", "wb").write(b"RIFF" + struct.pack("<I", len(body)) + body)
print("ok")
