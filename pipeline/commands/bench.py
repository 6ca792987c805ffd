"""rvsweep bench: performance figures of the core and the sweep, measured in one run."""
from __future__ import annotations

import json

HELP = ("performance figures: full study cycle on one core with each integrator, scipy comparison, "
        "sweep efficiency")

#: (label, figure of pipeline.bench.CYCLE_FIGURES, format) of the full-cycle table.
_CYCLE_ROWS = (
    ("wall time [s]", "full_cycle_wall_s", "12.2f"),
    ("integrator wall [s]", "integrator_wall_s", "12.2f"),
    ("steps", "steps", "12d"),
    ("time step [us]", "time_step_s", "12.3f"),
    ("held-load step [us]", "held_time_step_s", "12.3f"),
    ("RHS evaluations", "rhs_evaluations", "12d"),
    ("per ball per RHS [ns]", "ns_per_ball_rhs", "12.1f"),
    ("simulated s per wall s", "simulated_s_per_wall_s", "12.3f"),
)


def _counts(text: str, flag: str, what: str, lo: int, hi: int, example: str) -> tuple:
    """``flag text``: whole numbers separated by commas, each from ``lo`` to ``hi``, or a
    :class:`pipeline.errors.UserError` (one line naming the flag and the text, before any work)."""
    from ..errors import UserError

    try:
        counts = tuple(int(x) for x in text.split(","))
    except ValueError:
        counts = ()
    if not counts or any(not lo <= n <= hi for n in counts):
        raise UserError(f"{flag} {text!r}: expected {what} separated by commas, each from {lo} to {hi} "
                        f"(e.g. {example})")
    return counts


def _ball_counts(text: str) -> tuple:
    """``--balls 51,102,204``: from 12 (the scaled bore stays open) to the layout's limit."""
    from rvcore.bearing.layout import MAX_ROW_BALLS

    return _counts(text, "--balls", "ball counts", 12, MAX_ROW_BALLS, "51,102,204")


def _rounds(text: str) -> int:
    """``--rounds 5``: the side-by-side rounds of ``--balls``, a whole number from 1 to 100."""
    from ..errors import UserError

    try:
        n = int(text)
    except ValueError:
        n = 0
    if not 1 <= n <= 100:
        raise UserError(f"--rounds {text!r}: expected a whole number of rounds from 1 to 100 (e.g. 5)")
    return n


def _task_counts(text: str) -> tuple:
    """``--tasks 1000,10000``: numbers of stand-in cases from 1 to 1,000,000."""
    return _counts(text, "--tasks", "numbers of cases", 1, 1_000_000, "1000,10000")


def add_arguments(parser):
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--quick", action="store_true", help="skip the sweep parallel-efficiency run")
    parser.add_argument("--balls", default=None, metavar="Z,Z,...",
                        help="only the cost per ball-step of the study bearing scaled to these ball counts "
                             "(e.g. 51,102,204), over 0.03-0.1 s of the short cycle")
    parser.add_argument("--rounds", default=None, metavar="N",
                        help="with --balls: rounds timing every count side by side (default 5); the "
                             "figures are their medians, the ratio each round's own")
    parser.add_argument("--tasks", default=None, metavar="N,N,...",
                        help="only the parent's CPU per case on a 2-process local dask cluster, dask's "
                             "scheduler included, for N stand-in cases that compute nothing (e.g. 1000,10000)")


def run(args):
    from rvcore.integrate.methods import NAMES as METHODS

    from ..bench import run_all

    balls = _ball_counts(args.balls) if args.balls is not None else None
    tasks = _task_counts(args.tasks) if args.tasks is not None else None
    extra = {}
    if args.rounds is not None:
        if balls is None:
            from ..errors import UserError

            raise UserError(f"--rounds {args.rounds!r}: it counts the rounds of --balls, which is not given")
        extra["rounds"] = _rounds(args.rounds)
    figures = run_all(quick=args.quick, balls=balls, tasks=tasks, **extra)
    if args.json:
        print(json.dumps(figures, indent=1))
        return 0
    f = figures
    if tasks:
        print(f"Parent of a sweep on a local dask cluster of {f['scheduler_workers']} processes, stand-in cases "
              "that compute nothing (the scheduler runs in the parent)")
        print(f"  {'cases':>8s} {'parent CPU/case [ms]':>21s} {'wall [s]':>9s} {'cluster start [s]':>18s}")
        for n in tasks:
            print(f"  {n:8d} {f[f'parent_cpu_per_task_ms_{n}']:21.3f} {f[f'scheduler_wall_s_{n}']:9.1f} "
                  f"{f[f'cluster_start_s_{n}']:18.1f}")
        return 0
    if balls:
        t0, t1 = f["ball_scaling_window_s"]
        print(f"Study bearing scaled to Z balls (same spacing, same load a ball), short cycle {t0:g}-{t1:g} s, "
              f"660 deg/s, one core; medians of {f['ball_scaling_rounds']} rounds side by side")
        print(f"  {'balls':>6s} {'us/ball-step':>13s} {'x Z=' + str(balls[0]):>8s} {'range':>11s} {'steps':>8s} "
              f"{'substepped/step':>16s} {'refreshes/step':>15s}")
        for z in balls:
            lo, hi = f[f"ball_scaling_ratio_range_{z}"]
            print(f"  {z:6d} {f[f'us_per_ball_step_{z}']:13.3f} {f[f'ball_scaling_ratio_{z}']:8.2f} "
                  f"{lo:5.2f}-{hi:<5.2f} {f[f'ball_scaling_steps_{z}']:8d} "
                  f"{f[f'ball_scaling_substepped_per_step_{z}']:16.4f} "
                  f"{f[f'ball_scaling_refreshes_per_step_{z}']:15.4f}")
        return 0
    methods = [m for m in METHODS if f"{m}_full_cycle_wall_s" in f]
    print("Study bearing (51 balls), full 4.6 s cycle at 660 deg/s, 30 kN + 10 kN, one core "
          f"(default method: {f['method']})")
    print("  " + " " * 24 + "".join(f"{m:>12s}" for m in methods))
    for label, key, fmt in _CYCLE_ROWS:
        print(f"  {label:24s}" + "".join(format(f[f"{m}_{key}"] * (1e6 if key.endswith("time_step_s") else 1), fmt)
                                          for m in methods))
    if "rk4" in methods:
        print(f"  {'speedup vs rk4':24s}" + "".join(
            f"{f['rk4_full_cycle_wall_s'] / f[f'{m}_full_cycle_wall_s']:12.2f}" for m in methods))
    if "phase_names" in f:
        print(f"  where the {f['method']} integration's {f['phase_total_wall_s']:.2f} s go, stretch by stretch "
              "(one run a stretch, each from the state the last ended in)")
        print(f"    {'stretch':24s} {'window [s]':>12s} {'wall [s]':>9s} {'share':>6s} {'steps':>7s} {'us/step':>8s} "
              f"{'refreshes/step':>15s} {'substepped/step':>16s}")
        for k, name in enumerate(f["phase_names"]):
            a, b = f["phase_windows_s"][k]
            wall = f[f"phase_wall_s_{k}"]
            print(f"    {name:24s} {f'{a:g}-{b:g}':>12s} {wall:9.2f} {wall / f['phase_total_wall_s']:6.1%} "
                  f"{f[f'phase_steps_{k}']:7d} {f[f'phase_us_per_step_{k}']:8.1f} "
                  f"{f[f'phase_refreshes_per_step_{k}']:15.3f} {f[f'phase_substepped_per_step_{k}']:16.4f}")
    print(f"scipy solve_ivp(DOP853) on the same RHS, {f.get('scipy_window_s', float('nan')) * 1e3:.0f} ms window, "
          "matched accuracy (reference: rk4 at 1/8 of its step)")
    for prefix in ("rk4_", ""):
        m = f.get(f"{prefix}scipy_method", "?")
        if f"{prefix}scipy_ratio" not in f:
            continue
        print(f"  scipy / {m:4s} wall        {f[f'{prefix}scipy_ratio']:8.2f}x  "
              f"(scipy {f.get(f'{prefix}scipy_wall_s', float('nan')):.3f} s, "
              f"{m} {f.get(f'{prefix}ours_window_wall_s', float('nan')):.3f} s; "
              f"rtol {f.get(f'{prefix}scipy_rtol')}, errors {f.get(f'{prefix}scipy_position_error_m', float('nan')):.2e} "
              f"vs {f.get(f'{prefix}ours_position_error_m', float('nan')):.2e} m)")
    if "imperfection_cost_ratio" in f:
        print(f"Imperfections: the study case at ISO 492 Normal against perfect, first 0.6 s, median of pairs: "
              f"{f['imperfection_cost_ratio']:.3f}x ({f['imperfection_normal_wall_s']:.2f} s vs "
              f"{f['imperfection_perfect_wall_s']:.2f} s)")
    if "lubricated_cost_ratio" in f:
        at = ", ".join(f"{k.rsplit('_', 1)[1]} deg/s {v:.3f}x" for k, v in f.items()
                       if k.startswith("lubricated_cost_ratio_"))
        print(f"Lubricated law (ehl_bair_winer) against the dry one (coulomb_step), the whole study case, "
              f"median of pairs: {at}; largest {f['lubricated_cost_ratio']:.3f}x ({f['lubricated_wall_s']:.2f} s vs "
              f"{f['lubricated_dry_wall_s']:.2f} s; issue 40's goal: at most 1.3x)")
    if "flexible_cost_ratio" in f:
        for suffix, what in (("", "steady running"), ("_start", "the load ramp")):
            if f"flexible_cost_ratio{suffix}" not in f:
                continue
            start, end = f[f"flexible_window_s{suffix}"]
            print(f"Flexible rings (rv-main-flexible, modes to order 6) against rigid ones, {what} "
                  f"{start:g}-{end:g} s, median of pairs: {f[f'flexible_cost_ratio{suffix}']:.3f}x "
                  f"({f[f'flexible_wall_s{suffix}']:.2f} s vs {f[f'flexible_rigid_wall_s{suffix}']:.2f} s; step "
                  f"{f[f'flexible_time_step_s{suffix}'] * 1e6:.1f} vs {f[f'flexible_rigid_time_step_s{suffix}'] * 1e6:.1f} us, "
                  f"{f[f'flexible_us_per_step{suffix}']:.0f} vs {f[f'flexible_rigid_us_per_step{suffix}']:.0f} us a step; "
                  f"issue 41's goal: at most 1.5x)")
    if "coupling_cross_omega_h" in f:
        print(f"  the contacts' terms between the balls and the modes alone oscillate at omega*h "
              f"{f['coupling_cross_omega_h']:.2f} at the {f['coupling_time_step_s'] * 1e6:.1f} us step (the balls' own "
              f"{f['coupling_balls_omega_h']:.2f}, the modes' own {f['coupling_modes_omega_h']:.2f}); the explicit "
              "tableau's limit 2.83: they stay in the implicit solve")
    if "parallel_efficiency" in f:
        print(f"Smoke sweep ({f['smoke_cases']} cases, median of {f['smoke_repeats']}), first case submitted to last finished: serial "
              f"{f['smoke_serial_wall_s']:.1f} s, {f['smoke_workers']} workers {f['smoke_parallel_wall_s']:.1f} s")
        print(f"  parallel efficiency     {f['parallel_efficiency']:8.2f}  "
              f"(with warm-up and cluster start/stop: {f['parallel_efficiency_total']:.2f}, "
              f"{f['smoke_serial_total_s']:.1f} s vs {f['smoke_parallel_total_s']:.1f} s)")
    return 0
