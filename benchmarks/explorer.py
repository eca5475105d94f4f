"""Benchmark of the firing-order explorer: how the enumeration and the ranking scale with the cylinder count.

Run: python3 benchmarks/explorer.py [--max 12] [--repeat 3]
Prints, for in-line four-stroke engines of 4 to 12 cylinders, the numbers of crank arrangements and firing
orders, how many firing orders had their rule scores computed, and the best-of-N times of

* ``top 10``   the default: every arrangement scored for balance, firing orders only in the best tiers;
* ``all``      every firing order scored and ranked (up to 10 cylinders; 12 would mean 39.9 million rows).

Not part of the test suite (timings belong here, not in asserts). The acceptance goal is the in-line 8:
all 5040 firing orders ranked in well under 1 s.
"""

from __future__ import annotations

import argparse
import math
import time

from crankdyn.physics import firing_explorer as fe


def best_of(fn, repeat: int) -> tuple[float, object]:
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return min(times), value


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--max", type=int, default=12, help="largest cylinder count (default 12)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    fe.explore(4)  # imports and caches warm

    print(
        f"{'cyl':>4} {'arrangements':>13} {'firing orders':>14} {'scored (top 10)':>16} {'top 10, s':>10} "
        f"{'all, s':>8}"
    )
    for n in range(4, args.max + 1, 2):
        top_time, top = best_of(lambda: fe.explore(n, "inline", 4, top=10), args.repeat)  # noqa: B023 - called within this iteration
        if math.factorial(n - 1) <= 400_000:
            all_time, _ = best_of(
                lambda: fe.explore(n, "inline", 4, top=None), max(1, args.repeat // 2)
            )  # noqa: B023 - called within this iteration
            all_text = f"{all_time:8.3f}"
        else:
            all_text = f"{'-':>8}"
        print(
            f"{n:>4} {top.arrangements:>13,} {top.firing_orders:>14,} {top.scored_firing_orders:>16,} "
            f"{top_time:10.3f} {all_text}"
        )
    goal_time, result = best_of(lambda: fe.explore(8, "inline", 4, top=None), args.repeat)
    print(
        f"\nin-line 8, every one of the {result.firing_orders} firing orders ranked: {goal_time:.3f} s "
        f"(goal < 1 s: {'met' if goal_time < 1 else 'MISSED'})"
    )
    for layout, cylinders, gamma in (
        ("V", 8, 90.0),
        ("V", 12, 60.0),
        ("W", 12, 60.0),
        ("V", 16, 90.0),
    ):
        t, r = best_of(lambda: fe.explore(cylinders, layout, 4, gamma, top=10), args.repeat)  # noqa: B023 - called within this iteration
        print(
            f"{layout}{cylinders} {gamma:g} deg: {r.arrangements:,} arrangements, {r.firing_orders:,} firing "
            f"orders, top 10 in {t:.3f} s"
        )


if __name__ == "__main__":
    main()
