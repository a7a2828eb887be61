"""Writes short_stick_2khz.csv for host/tests/contact_not_told.rs with numpy (a record of the
campaign of synthetic recordings, 2026-11-27): a clean stick-slip at 2 kHz, 20 Hz cycles, 30 %
stick (30-row stick phases, shorter than the noise floor's 32-row blocks), slips of
a_rel = -J cos(pi tau / T_slip) with J = 10 m/s^2, noise 0.01 m/s^2 on each channel, 2 s.
True stick fraction 0.30475, 19.995 Hz.

    pip install numpy && python3 make_short_stick.py      # in this directory
"""
import numpy as np

FS, DUR, F_SS, SF, J, NOISE = 2000, 2.0, 20.0, 0.3, 10.0, 0.01
rng = np.random.default_rng(1)
n = int(round(DUR * FS))
t = np.arange(n) / FS
T = 1.0 / F_SS
Ts = (1 - SF) * T
ph = np.mod(t / T, 1.0) * T
slip = ph >= SF * T
a_rel = np.where(slip, -J * np.cos(np.pi * (ph - SF * T) / Ts), 0.0)
disc = np.zeros(n)
ch = [disc + rng.normal(0, NOISE, n), disc + a_rel + rng.normal(0, NOISE, n),
      disc + 0.6 * a_rel + rng.normal(0, NOISE, n), disc - 0.8 * a_rel + rng.normal(0, NOISE, n)]
np.savetxt("short_stick_2khz.csv", np.column_stack([t] + ch), fmt=["%.9f"] + ["%.9g"] * 4, delimiter=",",
           header="t,disc_x,pad_x,pad_trail,pad_lead", comments="")
print("stick fraction", np.mean(~slip))
