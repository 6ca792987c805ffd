"""rvsweep bench: performance figures of the core and the sweep, measured in one run."""
from __future__ import annotations

import json

HELP = "performance figures: full study cycle on one core, scipy comparison, sweep efficiency"


def add_arguments(parser):
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--quick", action="store_true", help="skip the sweep parallel-efficiency run")


def run(args):
    from ..bench import run_all

    figures = run_all(quick=args.quick)
    if args.json:
        print(json.dumps(figures, indent=1))
        return 0
    f = figures
    print("Study bearing (51 balls), full 4.6 s cycle at 660 deg/s, 30 kN + 10 kN, one core")
    print(f"  wall time               {f['full_cycle_wall_s']:8.2f} s  (integrator {f['integrator_wall_s']:.2f} s)")
    print(f"  steps                   {f['steps']:8d}  (dt {f['time_step_s'] * 1e6:.3f} us)")
    print(f"  RHS evaluations         {f['rhs_evaluations']:8d}")
    print(f"  per ball per RHS        {f['ns_per_ball_rhs']:8.1f} ns")
    print(f"  simulated s per wall s  {f['simulated_s_per_wall_s']:8.3f}")
    print(f"scipy solve_ivp(DOP853) on the same RHS, {f.get('scipy_window_s', float('nan')) * 1e3:.0f} ms window, matched accuracy")
    print(f"  scipy / ours wall       {f['scipy_ratio']:8.2f}x  (scipy {f.get('scipy_wall_s', float('nan')):.3f} s, "
          f"ours {f.get('ours_window_wall_s', float('nan')):.3f} s; rtol {f.get('scipy_rtol')}, "
          f"errors {f.get('scipy_position_error_m', float('nan')):.2e} vs {f.get('ours_position_error_m', float('nan')):.2e} m)")
    if "parallel_efficiency" in f:
        print(f"Smoke sweep ({f['smoke_cases']} cases, median of {f['smoke_repeats']}), first case submitted to last finished: serial "
              f"{f['smoke_serial_wall_s']:.1f} s, {f['smoke_workers']} workers {f['smoke_parallel_wall_s']:.1f} s")
        print(f"  parallel efficiency     {f['parallel_efficiency']:8.2f}  "
              f"(with warm-up and cluster start/stop: {f['parallel_efficiency_total']:.2f}, "
              f"{f['smoke_serial_total_s']:.1f} s vs {f['smoke_parallel_total_s']:.1f} s)")
    return 0
