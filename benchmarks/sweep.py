"""Benchmark of a design sweep's answer key: points per second, as ratios measured in one run.

Run from the repository root:

    python3 benchmarks/sweep.py                    # 10 000 points, 2 jobs, with a Dask cluster
    python3 benchmarks/sweep.py --points 2000 --no-dask

The grid is the bundled single-cylinder example (examples/petrol-1cyl.toml, default stages, the
answer key only) over engine speed x rod ratio x peak cycle pressure, so that every stage of the
key sees new inputs at every point. Measured, each in this one process and run:

* ``per point``: a sample of the grid through the whole pipeline point by point, the error study
  included (what a sweep computed for each point before it ran in chunks);
* ``chunked``: the whole grid as ``crankdyn sweep`` computes it (crankdyn.batch.grid_run): chunks of
  points on ``--jobs`` worker processes, the key's stages only, ``run_many`` where a stage has one,
  the study once for the base scene;
* ``dask``: the same on a local Dask cluster of ``--jobs`` worker processes, timed after a
  sweep of a few points has loaded crankdyn in the fresh workers (printed as the warm-up);
* ``bare numpy``: the kinematics, a polytropic (unrounded) pressure curve, the forces and the
  torque of the same grid written as plain numpy over points x angles in one thread
  (:func:`bare_numpy`), checked against the chunked sweep's answer key in the columns that do not
  depend on the diagram's rounding.

Prints points/s and the ratios of the acceptance: chunked >= 500 points/s on 2 cores, chunked
within 10x of bare numpy, dask >= 80 % of chunked; and the CPU seconds per point of the chunked
sweep (all its processes) and of bare numpy, which other work on a shared machine does not change.
Not part of the test suite; writes nothing.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import time
from pathlib import Path

import numpy as np

from crankdyn.batch.grid_run import execute_key
from crankdyn.batch.sweep import base_for, base_studies, sweep_from_args, variants
from crankdyn.batch.variants import RunOptions, execute, load_base
from crankdyn.cli import examples_dir

SCENE = examples_dir() / "petrol-1cyl.toml"
GOALS = {"points_per_s": 500.0, "of_numpy": 10.0, "dask_share": 0.8}


def grid_sets(points: int) -> list[str]:
    """``--set`` arguments of a grid of about ``points`` points: speed x rod ratio x peak
    pressure."""
    side = max(2, round((points / 1.25) ** (1 / 3)))  # 10 000 points: 25 speeds x 20 x 20
    speeds = max(2, points // (side * side))
    return [
        f"engine.rpm=2000:7000:{speeds}",
        f"engine.rod_ratio=0.24:0.32:{side}",
        f"cycle.max_pressure=4.5 MPa:7.5 MPa:{side}",
    ]


def bare_numpy(
    rpm, ratio, max_pressure_Pa, base: dict, step_deg: float = 1.0
) -> dict[str, np.ndarray]:
    """The sweep's formulas as plain numpy over points x angles (petrol-1cyl's masses and cycle).

    Kinematics of the central crank-slider (exact), the theoretical diagram's polytropes (no
    rounding), gas and inertia pressures, the tangential pressure and the torque of one crank.
    Returns per-point columns named as the answer key's (SI units as the key's).
    """
    engine, masses, cycle = base["engine"], base["masses"], base["cycle"]
    bore, stroke = _metres(engine["bore"]), _metres(engine["stroke"])
    radius = stroke / 2
    area = math.pi * bore**2 / 4
    omega = (math.pi * rpm / 30)[:, None]
    lam = ratio[:, None]
    alpha = np.radians(np.arange(0.0, 720.0, step_deg))[None, :]
    sin_a, cos_a = np.sin(alpha), np.cos(alpha)
    cos_b = np.sqrt(1 - (lam * sin_a) ** 2)
    s = radius * (1 - cos_a + (1 - cos_b) / lam)
    v = radius * omega * sin_a * (1 + lam * cos_a / cos_b)
    j = radius * omega**2 * (cos_a + lam * (cos_a**2 - sin_a**2 + lam**2 * sin_a**4) / cos_b**3)
    # the theoretical diagram: intake, polytropic compression, combustion at TDC, expansion, exhaust
    eps, n1, n2 = cycle["compression_ratio"], cycle["compression_index"], cycle["expansion_index"]
    p_a, p_r = _pascal(cycle["intake_pressure"]), _pascal(cycle["exhaust_pressure"])
    swept = area * stroke
    clearance = swept / (eps - 1)
    volume = clearance + area * s
    deg = np.degrees(alpha)
    compression = p_a * ((clearance + swept) / volume) ** n1
    p_c = p_a * eps**n1
    expansion = max_pressure_Pa[:, None] * (clearance / volume) ** n2
    pressure = np.where(
        deg < 180, p_a, np.where(deg < 360, compression, np.where(deg < 540, expansion, p_r))
    )
    m_piston, m_rod = _kilograms(masses["piston_group"]), _kilograms(masses["rod"])
    reciprocating = m_piston + m_rod * masses["rod_cm_fraction"]
    rotating = (
        m_rod * (1 - masses["rod_cm_fraction"])
        + _kilograms(masses["crank_pin"])
        + 2 * _kilograms(masses["crank_web"])
    )
    total = pressure - _pascal(engine["crankcase_pressure"]) - reciprocating * j / area
    sin_b = lam * sin_a
    tangential = total * (sin_a * cos_b + cos_a * sin_b) / cos_b
    torque = tangential * area * radius
    return {
        "v_mean_m_s": stroke * rpm / 30,
        "v_max_m_s": np.max(v, axis=1),
        "j_max_m_s2": j[:, 0],
        "j_min_m_s2": np.min(j, axis=1),
        "p_c_MPa": np.full(len(rpm), p_c) * 1e-6,
        "p_j_tdc_MPa": -reciprocating * j[:, 0] / area * 1e-6,
        "c_MPa": -rotating * radius * omega[:, 0] ** 2 / area * 1e-6,
        "M_cylinder_max_Nm": np.max(torque, axis=1),
    }


def _number(text, unit: str, scale: float) -> float:
    if isinstance(text, (int, float)):
        return float(text)
    value, given = text.split()
    assert given == unit, (text, unit)
    return float(value) * scale


def _metres(text) -> float:
    return _number(text, "mm", 1e-3)


def _pascal(text) -> float:
    return _number(text, "MPa", 1e6)


def _kilograms(text) -> float:
    return _number(text, "kg", 1.0)


#: Columns the bare numpy reference must reproduce, with the relative tolerance: closed forms to
#: round-off; extremes read off the 1° grid (the key's are root searches) to the grid's accuracy.
CHECKED = {
    "v_mean_m_s": 1e-12,
    "j_max_m_s2": 1e-12,
    "p_c_MPa": 1e-12,
    "p_j_tdc_MPa": 1e-12,
    "c_MPa": 1e-12,
    "v_max_m_s": 1e-4,
    "j_min_m_s2": 1e-3,
}


def check_reference(reference: dict[str, np.ndarray], outcomes) -> float:
    """The largest relative difference of the closed-form columns; raises if any checked column
    is beyond its tolerance."""
    worst = 0.0
    for column, tolerance in CHECKED.items():
        key = np.array([o.answers[column] for o in outcomes], dtype=float)
        difference = float(np.max(np.abs(reference[column] - key) / np.abs(key)))
        if difference > tolerance:
            raise AssertionError(
                f"bare numpy and the sweep differ in {column}: {difference:.3g} > {tolerance:g}"
            )
        worst = max(worst, difference) if tolerance < 1e-9 else worst
    return worst


def cpu_seconds() -> float:
    """CPU seconds (user + system) of this process and of its ended child processes (the local
    sweep's workers are ended when it returns)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _dask_options(jobs: int):
    from distributed import LocalCluster  # lazy: the optional dask extra

    return LocalCluster(
        n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=":0"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=10_000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument(
        "--sample", type=int, default=40, help="points run point by point (default 40)"
    )
    parser.add_argument("--no-dask", action="store_true")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

    sweep = sweep_from_args(grid_sets(args.points), None, None, None)
    base, base_dir = load_base(SCENE)
    base, _ = base_for(base, sweep)
    _, points = variants(sweep)
    options = RunOptions([], jobs=args.jobs, progress=False)
    print(
        f"grid: {len(points)} points of {SCENE.name} ({', '.join(grid_sets(args.points))}), "
        f"{args.jobs} jobs, {os.cpu_count()} cores"
    )

    sample = points[:: max(1, len(points) // args.sample)][: args.sample]
    start = time.perf_counter()
    slow, _ = execute(sample, base, base_dir, Path("."), options)
    per_point = len(sample) / (time.perf_counter() - start)

    start = time.perf_counter()
    notes = base_studies(base, base_dir, options)
    cpu_start = cpu_seconds()
    fast, _ = execute_key(points, base, base_dir, options)
    chunked_cpu = (cpu_seconds() - cpu_start) / len(points)
    chunked = len(points) / (time.perf_counter() - start)
    failed = [o for o in fast if not o.ok]

    by_row = {o.row: o for o in fast}
    worst = max(
        (
            abs(by_row[o.row].answers[c] - v) / abs(v)
            for o in slow
            for c, v in o.answers.items()
            if v not in (None, 0)
        ),
        default=0.0,
    )

    rpm = np.array([float(v.cells["engine.rpm"]) for v in points])
    ratio = np.array([float(v.cells["engine.rod_ratio"]) for v in points])
    peak = np.array([float(v.cells["cycle.max_pressure [MPa]"]) * 1e6 for v in points])
    start, cpu_start = time.perf_counter(), cpu_seconds()
    reference = bare_numpy(rpm, ratio, peak, base)
    numpy_cpu = (cpu_seconds() - cpu_start) / len(points)
    numpy_rate = len(points) / (time.perf_counter() - start)
    closed_form = check_reference(reference, fast)

    dask_rate = None
    if not args.no_dask:
        from distributed import Client  # lazy: the optional dask extra

        with _dask_options(args.jobs) as cluster:
            on_dask = RunOptions([], progress=False, scheduler=cluster.scheduler_address)
            # a fresh cluster's workers import crankdyn on their first task: a small sweep first,
            # so that the ratio compares throughput (the local workers fork a warmed process)
            start = time.perf_counter()
            execute_key(points[: 4 * args.jobs], base, base_dir, on_dask)
            dask_warm_s = time.perf_counter() - start
            with Client(cluster) as client:
                workers_before = sum(client.run(cpu_seconds).values())
            cpu_start = cpu_seconds()
            start = time.perf_counter()
            remote, _ = execute_key(points, base, base_dir, on_dask)
            dask_rate = len(points) / (time.perf_counter() - start)
            here = cpu_seconds() - cpu_start  # the scheduler and the client run in this process
            with Client(cluster) as client:
                workers = sum(client.run(cpu_seconds).values()) - workers_before
            dask_cpu = (here, workers)
            assert [o.answers for o in remote] == [o.answers for o in fast]

    print(f"notes: {'; '.join(notes)}")
    print(f"failed points: {len(failed)}")
    print(f"per point (whole pipeline, {len(sample)} points): {per_point:9.1f} points/s")
    print(
        f"chunked (the sweep's key):          {chunked:9.1f} points/s   "
        f"{chunked / per_point:6.1f}x per point;  goal >= {GOALS['points_per_s']:g}: "
        f"{chunked / GOALS['points_per_s']:.2f} of it"
    )
    print(
        f"bare numpy (1 thread):              {numpy_rate:9.1f} points/s   "
        f"chunked is {numpy_rate / chunked:.1f}x slower (goal <= {GOALS['of_numpy']:g}x)"
    )
    if dask_rate is not None:
        print(
            f"dask ({args.jobs} worker processes):          {dask_rate:9.1f} points/s   "
            f"{dask_rate / chunked:.0%} of chunked (goal >= {GOALS['dask_share']:.0%}); "
            f"workers warmed first in {dask_warm_s:.1f} s"
        )
        print(
            f"dask CPU time per point: workers {dask_cpu[1] / len(points) * 1e6:.0f} us, "
            f"scheduler and client {dask_cpu[0] / len(points) * 1e6:.0f} us "
            f"(chunked: {chunked_cpu * 1e6:.0f} us)"
        )
    print(
        f"CPU time per point (this process and its workers): chunked {chunked_cpu * 1e6:.0f} us, "
        f"bare numpy {numpy_cpu * 1e6:.0f} us: {chunked_cpu / numpy_cpu:.1f}x (on a shared "
        f"machine the wall-clock ratios follow the other load; these do not)"
    )
    idle = args.jobs / chunked_cpu
    print(
        f"chunked on {args.jobs} otherwise idle cores (jobs / CPU time per point): {idle:9.1f} "
        f"points/s;  goal >= {GOALS['points_per_s']:g}: {idle / GOALS['points_per_s']:.2f} of it"
    )
    print(
        f"machine load while measured (1, 5, 15 min): "
        f"{', '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores"
    )
    print(f"chunked vs per point, largest relative difference over the sample's key: {worst:.2g}")
    print(
        f"bare numpy vs the key, closed-form columns: largest relative difference {closed_form:.2g}"
    )


if __name__ == "__main__":
    main()
