"""A corpus of scenes generated from the bundled examples with a seeded random generator.

Every family varies one bundled example within physically valid limits (the scene validation
refuses the rest, so a refused scene here is a defect of the generator): in-line engines of 1 to
12 cylinders, V and W engines of several bank angles, boxers, single-row radials of 3 to 9
cylinders with articulated rods, two- and four-stroke, petrol and diesel cycles, a measured
pressure trace, a mechanism studied for its kinematics only, the offset crank-slider, the
planetary and the vane mechanisms and the example plugin's Scotch yoke. Each scene carries what
its text must agree with: the number of cranks, whether a flywheel is designed, whether a cycle
is computed.
"""

from __future__ import annotations

import copy
import random
from dataclasses import dataclass

from conftest import example_data
from test_extreme import even_firing_order

LANGUAGES = ("en", "uk", "ru")
#: The numerics study at its cheapest: one coarse step against the scene's, once.
CHEAP_NUMERICS = {"steps_deg": [10], "repeats": 1, "kinematics_forms": False}

_PETROL_CYCLE = example_data("inline4-petrol")["cycle"]
_DIESEL_CYCLE = example_data("diesel-1cyl")["cycle"]
_FLYWHEEL = example_data("inline4-petrol")["flywheel"]
#: the valve timing of a four-stroke cycle, which a two-stroke (port-scavenged) cycle has not
_FOUR_STROKE_TIMING = (
    "exhaust_closes_after_tdc_deg",
    "intake_opens_before_tdc_deg",
    "intake_closes_after_bdc_deg",
)


@dataclass(frozen=True)
class CorpusScene:
    """One generated scene: its data (a scene's dictionary), the language its note is checked in
    and what its text must agree with."""

    name: str
    data: dict
    language: str
    cranks: int  # crank pins on the shaft (0: no crankshaft of an engine)
    flywheel: bool  # a flywheel is designed
    cycle: bool  # a working cycle (gas forces) is computed
    plugin: bool = False  # needs the example plugin registered

    @property
    def single_crank(self) -> bool:
        return self.cranks <= 1


def _mm(value: float) -> str:
    return f"{value:.1f} mm"


def _kg(value: float) -> str:
    return f"{value:.3g} kg"


def _sizes(rng: random.Random, bore_mm: tuple[float, float]) -> tuple[float, float, float]:
    """(bore, stroke, λ) of a plausible engine: stroke/bore 0.8-1.25, λ 0.24-0.31."""
    bore = round(rng.uniform(*bore_mm), 1)
    return bore, round(bore * rng.uniform(0.8, 1.25), 1), round(rng.uniform(0.24, 0.31), 3)


def _masses(rng: random.Random, bore_mm: float) -> dict:
    """Masses scaled from the in-line four's (82 mm bore) with the cube of the bore."""
    scale = (bore_mm / 82.0) ** 3 * rng.uniform(0.85, 1.15)
    return {
        "piston_group": _kg(0.45 * scale),
        "rod": _kg(0.60 * scale),
        "rod_cm_fraction": round(rng.uniform(0.24, 0.32), 3),
        "crank_pin": _kg(0.35 * scale),
        "crank_web": _kg(0.25 * scale),
    }


def _cycle(rng: random.Random, diesel: bool, strokes: int) -> dict:
    cycle = copy.deepcopy(_DIESEL_CYCLE if diesel else _PETROL_CYCLE)
    # the thermal calculation's value of the example's engine
    cycle.pop("mean_indicated_pressure", None)
    if diesel:
        cycle["compression_ratio"] = round(rng.uniform(15.0, 19.0), 1)
        cycle["max_pressure"] = f"{rng.uniform(7.0, 10.0):.2f} MPa"
    else:
        cycle["compression_ratio"] = round(rng.uniform(8.0, 11.0), 1)
        cycle["max_pressure"] = f"{rng.uniform(5.0, 7.5):.2f} MPa"
    if strokes == 2:
        cycle.pop("exhaust_pressure", None)
        rounding = cycle.setdefault("rounding", {})
        for key in _FOUR_STROKE_TIMING:
            rounding.pop(key, None)
        rounding["exhaust_opens_before_bdc_deg"] = rng.choice([70, 80, 90])
    return cycle


def _analysis(rng: random.Random) -> dict:
    return {"angle_step_deg": None, "table_step_deg": rng.choice([30, 30, 15])}


def _report(language: str, title: str) -> dict:
    return {"title": title, "year": 2026, "language": language}


def _piston_engine(
    rng,
    language,
    *,
    layout,
    cylinders,
    bank=None,
    strokes=4,
    diesel=False,
    rod_type="central",
    flywheel=False,
) -> tuple[dict, int]:
    """An evenly firing engine of ``layout`` from the in-line four's data; (data, cranks)."""
    bore, stroke, rod_ratio = _sizes(rng, (95.0, 130.0) if diesel else (70.0, 100.0))
    data = copy.deepcopy(example_data("inline4-petrol"))
    data.pop("flywheel")
    engine = data["engine"]
    engine.pop("effective_power")
    engine.update(
        name=f"{layout} {cylinders}",
        strokes=strokes,
        cylinders=cylinders,
        layout=layout,
        rpm=rng.randrange(1600, 2800, 100) if diesel else rng.randrange(3000, 6200, 100),
        bore=_mm(bore),
        stroke=_mm(stroke),
        rod_ratio=rod_ratio,
        rod_type=rod_type,
        cylinder_spacing=_mm(bore * rng.uniform(1.15, 1.3)),
    )
    if cylinders > 1:
        engine["firing_order"] = even_firing_order(layout, cylinders, strokes, bank)
    else:
        engine.pop("firing_order")
    if bank is not None:
        engine["bank_angle_deg"] = bank
    data["masses"] = _masses(rng, bore)
    data["cycle"] = _cycle(rng, diesel, strokes)
    data["analysis"] = _analysis(rng)
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"] = _report(language, f"Dynamic calculation of a {layout} engine")
    if flywheel:
        data["flywheel"] = copy.deepcopy(_FLYWHEEL)
    pins_per_crank = {"inline": 1, "V": 2, "boxer": 1, "W": 3}[layout]  # a boxer: a pin each
    return data, cylinders // pins_per_crank


def _inline(rng, language, index):
    cylinders = index + 1  # 1 to 12, each once
    strokes = rng.choice([2, 4, 4])
    diesel = rng.random() < 0.4
    flywheel = cylinders > 1 and rng.random() < 0.5
    data, cranks = _piston_engine(
        rng,
        language,
        layout="inline",
        cylinders=cylinders,
        strokes=strokes,
        diesel=diesel,
        flywheel=flywheel,
    )
    name = f"inline{cylinders}-{strokes}s-{'diesel' if diesel else 'petrol'}"
    return name, data, cranks, flywheel, True


#: (layout, cylinders, bank angle, strokes) of engines that can fire evenly
_BANKED = [
    ("V", 4, 90, 2),
    ("V", 4, 180, 4),
    ("V", 6, 60, 2),
    ("V", 6, 120, 4),
    ("V", 8, 90, 4),
    ("V", 8, 90, 2),
    ("V", 10, 72, 4),
    ("V", 12, 60, 4),
    ("V", 12, 60, 2),
    ("W", 3, 120, 4),
    ("W", 6, 60, 2),
    ("W", 12, 60, 4),
    ("boxer", 2, None, 2),
    ("boxer", 4, None, 4),
    ("boxer", 6, None, 4),
]


def _banked(rng, language, index):
    layout, cylinders, bank, strokes = _BANKED[index]
    diesel = layout == "V" and rng.random() < 0.3
    rod_type = rng.choice(["central", "fork"]) if layout == "V" else "central"
    flywheel = rng.random() < 0.4
    data, cranks = _piston_engine(
        rng,
        language,
        layout=layout,
        cylinders=cylinders,
        bank=bank,
        strokes=strokes,
        diesel=diesel,
        rod_type=rod_type,
        flywheel=flywheel,
    )
    name = (
        f"{layout}{cylinders}-{strokes}s"
        + (f"-{bank}" if bank else "")
        + ("-diesel" if diesel else "")
    )
    return name, data, cranks, flywheel, True


_RADIAL = [(3, 4), (5, 4), (7, 4), (9, 4), (4, 2), (6, 2), (8, 2)]


def _radial(rng, language, index):
    cylinders, strokes = _RADIAL[index]
    data = copy.deepcopy(example_data("radial9-aircraft"))
    data["engine"].update(
        cylinders=cylinders,
        strokes=strokes,
        rpm=rng.randrange(1800, 2700, 100),
        name=f"Radial {cylinders}",
    )
    data["articulated"]["pin_radius"] = _mm(rng.uniform(60.0, 72.0))
    if strokes == 2:
        data["cycle"] = _cycle(rng, False, 2)
    data["analysis"] = _analysis(rng)
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"] = _report(language, "Dynamic calculation of a radial aircraft engine")
    return f"radial{cylinders}-{strokes}s", data, 1, False, True


def _trace(rng, language, index):
    example = ("inline6-diesel-trace", "diesel-rk-trace")[index % 2]
    data = copy.deepcopy(example_data(example))
    scale = rng.uniform(0.9, 1.1)
    for key in ("piston_group", "rod", "crank_pin", "crank_web"):
        data["masses"][key] = _kg(float(data["masses"][key].split()[0]) * scale)
    data["analysis"] = _analysis(rng)
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"]["language"] = language
    cranks = data["engine"].get("cylinders", 1)
    return f"{example}-{index}", data, cranks, False, True


def _single(rng, language, index):
    example = ("petrol-1cyl", "diesel-1cyl", "two-stroke-1cyl", "petrol-1cyl")[index]
    data = copy.deepcopy(example_data(example))
    data["engine"]["rpm"] = int(data["engine"]["rpm"] * rng.uniform(0.85, 1.1))
    data["analysis"] = {**_analysis(rng), "kinematics": rng.choice(["exact", "approximate"])}
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"]["language"] = language
    return f"{example}-{index}", data, 1, False, True


def _kinematics_only(rng, language, index):
    data = copy.deepcopy(example_data("kinematics-only"))
    data["engine"].pop("rod_length")
    data["engine"].update(
        rod_ratio=round(rng.uniform(0.2, 0.35), 3), rpm=rng.randrange(1500, 7000, 500)
    )
    data["analysis"] = {**_analysis(rng), "kinematics": rng.choice(["exact", "approximate"])}
    data["report"]["language"] = language
    return f"kinematics-only-{index}", data, 1, False, False


def _offset(rng, language, index):
    data = copy.deepcopy(example_data("offset-crank-engine"))
    data["mechanism"]["offset"] = _mm(rng.choice([-1, 1]) * rng.uniform(2.0, 20.0))
    data["engine"]["rpm"] = rng.randrange(3000, 6000, 100)
    data["rod_dynamics"]["model"] = rng.choice(["two_mass", "three_mass", "correction_couple"])
    data["analysis"] = _analysis(rng)
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"]["language"] = language
    return f"offset-{index}", data, 1, False, True


def _planetary(rng, language, index):
    data = copy.deepcopy(example_data("planetary-kinematics"))
    data["engine"]["rpm"] = rng.randrange(1500, 6000, 500)
    data["masses"]["piston_group"] = _kg(rng.uniform(0.3, 0.6))
    data["mechanism"]["pressure_angle_deg"] = rng.choice([20, 25])
    data["analysis"] = _analysis(rng)
    data["report"]["language"] = language
    return f"planetary-{index}", data, 1, False, False


def _vane(rng, language, index):
    data = copy.deepcopy(example_data("vane-engine-kinematics"))
    data["engine"]["rod_ratio"] = round(rng.uniform(0.5, 0.85), 2)
    data["engine"]["rpm"] = rng.randrange(1500, 6000, 500)
    data["mechanism"]["compare_rod_ratios"] = [rng.choice([0.4, 0.6, 0.7])]
    data["analysis"] = _analysis(rng)
    data["report"]["language"] = language
    return f"vane-{index}", data, 1, False, False


def _scotch_yoke(rng, language, index):
    """The example plugin: a rod-less mechanism, for its kinematics or under a petrol cycle."""
    if index == 0:
        data = {
            "engine": {
                "mechanism": "scotch_yoke",
                "strokes": 2,
                "rpm": rng.randrange(1000, 3000, 250),
                "bore": "60 mm",
                "stroke": "80 mm",
                "rod_ratio": 0.25,
            },
            "scotch_yoke": {"table_step_deg": 45},
            "report": _report(language, "Scotch yoke"),
        }
        return "scotch-yoke-kinematics", data, 1, False, False
    data = copy.deepcopy(example_data("petrol-1cyl"))
    data["engine"]["mechanism"] = "scotch_yoke"
    data["numerics"] = dict(CHEAP_NUMERICS)
    data["report"]["language"] = language
    return "scotch-yoke-engine", data, 1, False, True


#: (family, how many scenes it gives); 60 in all.
FAMILIES = (
    (_inline, 12),
    (_banked, len(_BANKED)),
    (_radial, len(_RADIAL)),
    (_trace, 3),
    (_single, 4),
    (_kinematics_only, 4),
    (_offset, 5),
    (_planetary, 4),
    (_vane, 4),
    (_scotch_yoke, 2),
)


def corpus(seed: int, languages=None) -> list[CorpusScene]:
    """The scenes of ``seed``; each in one language, the three in turn (``languages``: each scene in
    each of these instead)."""
    rng = random.Random(seed)
    scenes = []
    for family, count in FAMILIES:
        for index in range(count):
            name, data, cranks, flywheel, cycle = family(rng, LANGUAGES[0], index)
            for language in languages or (LANGUAGES[len(scenes) % len(LANGUAGES)],):
                data = copy.deepcopy(data)
                data["report"]["language"] = language
                scenes.append(
                    CorpusScene(
                        f"{seed}-{name}-{language}",
                        data,
                        language,
                        cranks,
                        flywheel,
                        cycle,
                        plugin=family is _scotch_yoke,
                    )
                )
    return scenes
