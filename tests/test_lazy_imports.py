"""scipy imported on first use (crankdyn.physics.lazy): the physics modules and the built-in
plugins import without it, a stage that calls it imports it then (a root or an extreme does not:
crankdyn.physics.scalar_search), and the stage's run time in the report does not include that
import."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

from crankdyn.engine.orchestrator import run_stage
from crankdyn.physics import lazy
from crankdyn.plugin.types import Stage, StageOutput, StagePresentation


def test_the_physics_and_the_plugins_import_without_scipy_and_import_it_when_called():
    code = textwrap.dedent("""
        import sys
        import crankdyn.output.pipeline, crankdyn.scene.model
        from crankdyn.plugin.registry import default_registry
        from crankdyn.physics import articulated, extrema, flywheel, kinematics, planetary, speed_fluctuation, torsion
        registry = default_registry()
        assert "scipy" not in sys.modules, sorted(m for m in sys.modules if m.startswith("scipy"))[:5]
        # roots and extremes are found without scipy (crankdyn.physics.scalar_search)
        v_max, angle = kinematics.max_piston_velocity_exact(0.04, 0.25, 600.0)
        assert "scipy" not in sys.modules and v_max > 0
        from crankdyn.physics.lazy import integrate
        assert integrate.solve_ivp is not None and "scipy.integrate" in sys.modules
        print("ok")
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr


def test_a_stage_is_timed_without_the_import_its_first_call_makes(tmp_path, monkeypatch):
    (tmp_path / "slow_to_import.py").write_text(
        "import time\ntime.sleep(0.3)\nVALUE = 7\n", encoding="utf-8"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    slow = lazy.LazyModule("slow_to_import")

    def run(scene, inputs):
        return StageOutput(results={"value": slow.VALUE})

    stage = Stage(
        name="uses_slow",
        requires=(),
        provides=(),
        applies=lambda scene: None,
        run=run,
        presentation=StagePresentation(title_key="x", render=lambda output, ctx: ""),
    )
    before = lazy.import_seconds()
    start = time.perf_counter()
    output, elapsed = run_stage(stage, None, {})
    outer = time.perf_counter() - start
    imported = lazy.import_seconds() - before
    assert output.results["value"] == 7
    assert imported >= 0.3  # the import was counted (the module sleeps 0.3 s) ...
    # ... and left out of the stage's time: an accounting identity, whatever the machine's speed
    assert 0 < elapsed <= outer - imported + 1e-6, (elapsed, outer, imported)
    sys.modules.pop("slow_to_import", None)
