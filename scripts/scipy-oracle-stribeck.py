#!/usr/bin/env python3
"""SciPy's event-driven DOP853 on the 1-DOF Stribeck oracle (oracle_stribeck, 6 s): stick in
closed form (x = x0 + V t until k x + c_x V reaches mu_s N), slip integrated with
solve_ivp(method="DOP853") with the end of slip (v = 0) and the extremes of x (x' = 0) as events.
Prints, per tolerance, the error as `stickslip accuracy` measures model 2 (the larger relative
error of the mean period over the slip onsets at t >= stats_from and of the x peak-to-peak over
[stats_from, 6 s]) and the in-process CPU time (process_time, best of several runs: comparable with perf stat's
task-clock on a loaded machine).

    pip install numpy scipy
    python3 scripts/scipy-oracle-stribeck.py PERIOD_S X_PP_M

PERIOD_S and X_PP_M: the model-2 reference's values, printed on the first line of
`cargo run --release -p stickslip --example event_speed` (DOP853 at rtol 1e-12 in Rust). Compare
the times with `perf stat -r 20 target/release/stickslip simulate oracle_stribeck` (whole process).
"""
import math
import sys
import time

from scipy.integrate import solve_ivp

M, K, V, MU_S, MU_K, N0, V_S = 1.0, 100.0, 0.02, 0.6, 0.4, 10.0, 0.01
C_X = N0 * (MU_S - MU_K) / V_S * math.exp(-0.03 / V_S)
T_END, STATS_FROM = 6.0, 1.3


def mu(v):
    return MU_K + (MU_S - MU_K) * math.exp(-abs(v) / V_S)


def run(rtol, atol):
    t, x, regime, sigma = 0.0, 0.0, "stick", 0.0
    onsets, xs = [], []
    while t < T_END:
        if regime == "stick":
            # k x + c V = +-mu_s N with x = x0 + V (t' - t)
            tb = t + (MU_S * N0 - C_X * V - K * x) / (K * V)
            if t < STATS_FROM < min(tb, T_END):
                xs.append((STATS_FROM, x + V * (STATS_FROM - t)))
            if tb >= T_END:
                xs.append((T_END, x + V * (T_END - t)))
                xs.append((t, x))
                break
            xs.append((t, x))
            x += V * (tb - t)
            t = tb
            xs.append((t, x))
            onsets.append(t)
            regime, sigma = "slip", 1.0
            y0 = [x, V]
        rhs = lambda _t, y: [y[1], (-K * y[0] - C_X * y[1] + sigma * mu(y[1] - V) * N0) / M]
        end = lambda _t, y: sigma * (y[1] - V) if _t > t else -1.0
        end.terminal, end.direction = True, 1.0
        crest = lambda _t, y: y[1]
        sol = solve_ivp(rhs, (t, T_END), y0, method="DOP853", rtol=rtol, atol=atol, events=(end, crest))
        for tc, yc in zip(sol.t_events[1], sol.y_events[1]):
            xs.append((tc, yc[0]))
        if sol.status == 1 and len(sol.t_events[0]):
            t = sol.t_events[0][0]
            x, xd = sol.y_events[0][0]
            xs.append((t, x))
            f_req = K * x + C_X * V
            if abs(f_req) <= MU_S * N0:
                regime = "stick"
            else:
                sigma = 1.0 if f_req > 0 else -1.0
                y0 = [x, V]
        else:
            xs.append((T_END, sol.y[0][-1]))
            break
    on = [o for o in onsets if o >= STATS_FROM]
    period = (on[-1] - on[0]) / (len(on) - 1)
    w = [v for (tt, v) in xs if tt >= STATS_FROM]
    return period, max(w) - min(w)


def main():
    p_ref, a_ref = float(sys.argv[1]), float(sys.argv[2])
    print(f"{'rtol':>8}  {'error':>9}  {'time [ms]':>9}")
    for rtol in [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]:
        p, a = run(rtol, rtol * 1e-3)
        err = max(abs(p - p_ref) / p_ref, abs(a - a_ref) / a_ref)
        best = min(timed(rtol) for _ in range(10))
        print(f"{rtol:>8.0e}  {err:>9.2e}  {best * 1e3:>9.2f}")


def timed(rtol):
    t0 = time.process_time()
    run(rtol, rtol * 1e-3)
    return time.process_time() - t0


if __name__ == "__main__":
    main()
