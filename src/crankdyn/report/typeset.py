"""Typesetting of what a reader sees: symbols, sub- and superscripts, numbers with units.

Catalog texts and stage code write a subscript the short way, ``s_п`` or ``p_z′``, and a power
``10^−16`` or ``cos^2``; tables and equations write ``<i>s</i><sub>p</sub>``. This module turns
both into typeset mathematics for the medium: real ``<sub>``/``<sup>`` in HTML (hence the PDF),
matplotlib mathtext in figures. One symbol table gives each quantity's subscript per language,
its unit and its meaning, so ``s_p`` in a table header and ``s_п`` in the running text of a
Ukrainian report come out as the same symbol. A report's table is a :class:`SymbolTable` built
for its run (:func:`symbol_table`): the core's symbols (:data:`SYMBOLS`, never changed) and those
the registry's stages declare; every function here takes the table to read (the core's by default).

Nothing here computes physics or changes a number's value.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, replace

import numpy as np

from ..errors import PluginError
from ..plugin.types import Symbol
from .i18n import MINUS, NARROW_NBSP, superscript

#: The report's symbols, keyed by a stable name: those whose subscript differs between the
#: languages (the textbook's Cyrillic subscripts in uk/ru, Latin ones in English) and the
#: main quantities every calculation uses. The list of symbols in front of the introduction is
#: printed from this table, with the symbols the report actually shows.
#: ``Symbol.sections`` of a core symbol whose meaning holds only in the sections of the stages that
#: declare it (``StagePresentation.section_symbols``: the side force n of the force sections, δ the
#: irregularity of the flywheel's); in a table no stage of the registry declares it for, it holds
#: nowhere.
SECTION_BOUND = ("<declaring stages>",)

_CORE_SYMBOLS: dict[str, Symbol] = {
    "crank_angle": Symbol("α", {}, "°", "symbol.crank_angle"),
    "rod_angle": Symbol("β", {}, "°", "symbol.rod_angle"),
    "bank_angle": Symbol("γ", {}, "°", "symbol.bank_angle"),
    "cylinder_bore": Symbol("D", {}, "unit.mm", "symbol.cylinder_bore"),
    "stroke": Symbol("S", {}, "unit.mm", "symbol.stroke"),
    "crank_radius": Symbol("R", {}, "unit.mm", "symbol.crank_radius"),
    "rod_length": Symbol("L", {}, "unit.mm", "symbol.rod_length"),
    "rod_ratio": Symbol("λ", {}, "", "symbol.rod_ratio"),
    "crank_speed": Symbol("n", {}, "unit.rpm", "symbol.crank_speed"),
    "crank_angular_velocity": Symbol("ω", {}, "unit.rad_s", "symbol.crank_angular_velocity"),
    "piston_displacement": Symbol(
        "s", {"en": "p", "uk": "п", "ru": "п"}, "unit.mm", "symbol.piston_displacement"
    ),
    "piston_velocity": Symbol(
        "v", {"en": "p", "uk": "п", "ru": "п"}, "unit.m_s", "symbol.piston_velocity"
    ),
    "piston_acceleration": Symbol(
        "j", {"en": "p", "uk": "п", "ru": "п"}, "unit.m_s2", "symbol.piston_acceleration"
    ),
    "rod_angular_velocity": Symbol(
        "ω", {"en": "r", "uk": "ш", "ru": "ш"}, "unit.rad_s", "symbol.rod_angular_velocity"
    ),
    "rod_angular_acceleration": Symbol(
        "ε", {"en": "r", "uk": "ш", "ru": "ш"}, "unit.rad_s2", "symbol.rod_angular_acceleration"
    ),
    "rod_mass": Symbol("m", {"en": "r", "uk": "ш", "ru": "ш"}, "unit.kg", "symbol.rod_mass"),
    "piston_group_mass": Symbol(
        "m", {"en": "pg", "uk": "п", "ru": "п"}, "unit.kg", "symbol.piston_group_mass"
    ),
    "reciprocating_mass": Symbol("m", {"en": "s"}, "unit.kg", "symbol.reciprocating_mass"),
    "rod_rotating_mass": Symbol("m", {"en": "rR"}, "unit.kg", "symbol.rod_rotating_mass"),
    "piston_area": Symbol("F", {"en": "p", "uk": "п", "ru": "п"}, "unit.cm2", "symbol.piston_area"),
    "swept_volume": Symbol("V", {"en": "h"}, "unit.l", "symbol.swept_volume"),
    "clearance_volume": Symbol("V", {"en": "c"}, "unit.l", "symbol.clearance_volume"),
    "max_pressure": Symbol("p", {"en": "z"}, "unit.MPa", "symbol.max_pressure"),
    "mean_indicated_pressure": Symbol(
        "p", {"en": "i"}, "unit.MPa", "symbol.mean_indicated_pressure"
    ),
    "indicated_work": Symbol("L", {"en": "i"}, "unit.J", "symbol.indicated_work"),
    "pumping_work": Symbol(
        "L", {"en": "pump", "uk": "нас", "ru": "нас"}, "unit.J", "symbol.pumping_work"
    ),
    "pumping_mean_pressure": Symbol(
        "p", {"en": "pump", "uk": "нас", "ru": "нас"}, "unit.MPa", "symbol.pumping_mean_pressure"
    ),
    "crankcase_pressure": Symbol("p", {"en": "0"}, "unit.MPa", "symbol.crankcase_pressure"),
    "gas_pressure": Symbol(
        "p", {"en": "g", "uk": "г", "ru": "г"}, "unit.MPa", "symbol.gas_pressure"
    ),
    "inertia_pressure": Symbol("p", {"en": "j"}, "unit.MPa", "symbol.inertia_pressure"),
    "inertia_first_order": Symbol("p", {"en": "jI"}, "unit.MPa", "symbol.inertia_first_order"),
    "inertia_second_order": Symbol("p", {"en": "jII"}, "unit.MPa", "symbol.inertia_second_order"),
    "total_pressure": Symbol("p", {"en": "1"}, "unit.MPa", "symbol.total_pressure"),
    "crank_torque": Symbol(
        "M", {"en": "k", "uk": "к", "ru": "к"}, "unit.Nm", "symbol.crank_torque"
    ),
    "driving_torque": Symbol(
        "M", {"en": "d", "uk": "д", "ru": "д"}, "unit.Nm", "symbol.driving_torque"
    ),
    "mean_speed": Symbol(
        "v", {"en": "mean", "uk": "сер", "ru": "ср"}, "unit.m_s", "symbol.mean_speed"
    ),
    "compression_ratio": Symbol("ε", {}, "", "symbol.compression_ratio"),
    "compression_polytrope": Symbol("n", {"en": "1"}, "", "symbol.compression_polytrope"),
    "expansion_polytrope": Symbol("n", {"en": "2"}, "", "symbol.expansion_polytrope"),
    "pre_expansion_ratio": Symbol("ρ", {}, "", "symbol.pre_expansion_ratio"),
    "pressure_rise_ratio": Symbol("λ", {"en": "p"}, "", "symbol.pressure_rise_ratio"),
    "intake_end_pressure": Symbol("p", {"en": "a"}, "unit.MPa", "symbol.intake_end_pressure"),
    "compression_end_pressure": Symbol(
        "p", {"en": "c"}, "unit.MPa", "symbol.compression_end_pressure"
    ),
    "expansion_end_pressure": Symbol("p", {"en": "b"}, "unit.MPa", "symbol.expansion_end_pressure"),
    "tangential_specific": Symbol("t", {}, "unit.MPa", "symbol.tangential_specific"),
    "radial_specific": Symbol(
        "z", {}, "unit.MPa", "symbol.radial_specific", sections=SECTION_BOUND
    ),
    "rod_specific": Symbol("k", {}, "unit.MPa", "symbol.rod_specific", sections=SECTION_BOUND),
    # N, not the textbook's n, which is the crank speed throughout the note (Kolchin's N)
    "side_specific": Symbol("N", {}, "unit.MPa", "symbol.side_specific", sections=SECTION_BOUND),
    "pin_resultant_specific": Symbol("q", {}, "unit.MPa", "symbol.pin_resultant_specific"),
    "rod_cm_distance": Symbol("l", {"en": "R"}, "unit.mm", "symbol.rod_cm_distance"),
    "crank_pin_mass": Symbol(
        "m", {"en": "cp", "uk": "ш.ш", "ru": "ш.ш"}, "unit.kg", "symbol.crank_pin_mass"
    ),
    "crank_web_mass": Symbol(
        "m", {"en": "w", "uk": "щ", "ru": "щ"}, "unit.kg", "symbol.crank_web_mass"
    ),
    "crank_rotating_mass": Symbol("m", {"en": "R"}, "unit.kg", "symbol.crank_rotating_mass"),
    "centrifugal_specific": Symbol("c", {}, "unit.MPa", "symbol.centrifugal_specific"),
    "rod_centrifugal_specific": Symbol(
        "c", {"en": "r"}, "unit.MPa", "symbol.rod_centrifugal_specific"
    ),
    "centrifugal_force": Symbol(
        "C", {}, "unit.N", "symbol.centrifugal_force", sections=SECTION_BOUND
    ),
    "first_order_amplitude": Symbol("C", {"en": "I"}, "unit.N", "symbol.first_order_amplitude"),
    "second_order_amplitude": Symbol("C", {"en": "II"}, "unit.N", "symbol.second_order_amplitude"),
    "order_amplitude": Symbol(
        "C", {"en": "ν"}, "unit.N", "symbol.order_amplitude", html="<i>C</i><sub><i>ν</i></sub>"
    ),
    "acceleration_harmonic": Symbol(
        "A", {"en": "ν"}, "", "symbol.acceleration_harmonic", html="<i>A</i><sub><i>ν</i></sub>"
    ),
    "total_volume": Symbol("V", {"en": "a"}, "unit.l", "symbol.total_volume"),
    # δ is the irregularity in the flywheel sections: both meanings scoped, so the list says where each holds
    "post_expansion_ratio": Symbol(
        "δ", {}, "", "symbol.post_expansion_ratio", sections=SECTION_BOUND
    ),
    "journal_diameter": Symbol(
        "d", {}, "unit.mm", "symbol.journal_diameter", sections=SECTION_BOUND
    ),
    # B is also a semi-axis of the balancing section's ellipses: the bearing width belongs to its section
    "bearing_width": Symbol("B", {}, "unit.mm", "symbol.bearing_width", sections=SECTION_BOUND),
    # flywheel and speed fluctuation: the textbook's Cyrillic subscripts in uk/ru
    "mechanism_mean_inertia": Symbol(
        "J", {"en": "m", "uk": "мех", "ru": "мех"}, "unit.kg_m2", "symbol.mechanism_mean_inertia"
    ),
    "shaft_inertia": Symbol(
        "J", {"en": "e", "uk": "в", "ru": "в"}, "unit.kg_m2", "symbol.shaft_inertia"
    ),
    "flywheel_inertia": Symbol(
        "J", {"en": "f", "uk": "мах", "ru": "мах"}, "unit.kg_m2", "symbol.flywheel_inertia"
    ),
    "required_inertia": Symbol("J", {"en": "0"}, "unit.kg_m2", "symbol.required_inertia"),
    "rim_inertia": Symbol(
        "J", {"en": "rim", "uk": "об", "ru": "об"}, "unit.kg_m2", "symbol.rim_inertia"
    ),
    "rim_thin_mass": Symbol(
        "m", {"en": "rim", "uk": "об", "ru": "об"}, "unit.kg", "symbol.rim_thin_mass"
    ),
    "rim_mean_diameter": Symbol(
        "D", {"en": "m", "uk": "сер", "ru": "ср"}, "unit.mm", "symbol.rim_mean_diameter"
    ),
    "rim_outer_diameter": Symbol(
        "D", {"en": "o", "uk": "з", "ru": "н"}, "unit.mm", "symbol.rim_outer_diameter"
    ),
    "rim_speed": Symbol("v", {"en": "o", "uk": "з", "ru": "н"}, "unit.m_s", "symbol.rim_speed"),
    "mean_angular_velocity": Symbol(
        "ω", {"en": "m", "uk": "сер", "ru": "ср"}, "unit.rad_s", "symbol.mean_angular_velocity"
    ),
    "mean_torque": Symbol(
        "M", {"en": "m", "uk": "сер", "ru": "ср"}, "unit.Nm", "symbol.mean_torque"
    ),
    "torque_max": Symbol("M", {"en": "max"}, "unit.Nm", "symbol.torque_max"),
    "torque_min": Symbol("M", {"en": "min"}, "unit.Nm", "symbol.torque_min"),
    "torque_non_uniformity": Symbol("μ", {}, "", "symbol.torque_non_uniformity"),
    # the time of one cycle (ω_m = Φ/T, the speed fluctuation's time-mean speed)
    "cycle_period": Symbol("T", {}, "unit.s", "symbol.cycle_period"),
    "indicated_power": Symbol("N", {"en": "i"}, "unit.kW", "symbol.indicated_power"),
    "effective_power": Symbol("N", {"en": "e"}, "unit.kW", "symbol.effective_power"),
    "pumping_power": Symbol(
        "N", {"en": "p", "uk": "нх", "ru": "нх"}, "unit.kW", "symbol.pumping_power"
    ),
    "mechanical_efficiency": Symbol(
        "η", {"en": "m", "uk": "м", "ru": "м"}, "", "symbol.mechanical_efficiency"
    ),
    "effective_torque": Symbol("M", {"en": "e"}, "unit.Nm", "symbol.effective_torque"),
    "indicated_torque": Symbol(
        "M", {"en": "i"}, "unit.Nm", "symbol.indicated_torque", sections=SECTION_BOUND
    ),
    "gas_torque": Symbol("M", {"en": "g", "uk": "г", "ru": "г"}, "unit.Nm", "symbol.gas_torque"),
    "resistance_torque": Symbol(
        "M", {"en": "c", "uk": "оп", "ru": "с"}, "unit.Nm", "symbol.resistance_torque"
    ),
    "cranks_count": Symbol("i", {"en": "k", "uk": "к", "ru": "к"}, "", "symbol.cranks_count"),
    "reference_value": Symbol(
        "X", {"en": "ref", "uk": "ет", "ru": "эт"}, "", "symbol.reference_value"
    ),
    "material_density": Symbol(
        "ρ", {"en": "mat", "uk": "м", "ru": "м"}, "unit.kg_m3", "symbol.material_density"
    ),
    "irregularity": Symbol("δ", {}, "", "symbol.irregularity", sections=SECTION_BOUND),
    # the quantities of the equations that the "де …" lines explain (crankdyn.report.equation_legend)
    "cylinder_pressure": Symbol("p", {}, "unit.MPa", "symbol.cylinder_pressure"),
    "bearing_pressure": Symbol(
        "p", {}, "unit.MPa", "symbol.bearing_pressure", sections=SECTION_BOUND
    ),
    "cylinder_volume": Symbol("V", {}, "unit.l", "symbol.cylinder_volume"),
    "theoretical_mean_indicated_pressure": Symbol(
        "p",
        {"en": "i"},
        "unit.MPa",
        "symbol.theoretical_mean_indicated_pressure",
        html="<i>p</i><sub>i</sub>′",
    ),
    "theoretical_indicated_work": Symbol(
        "L",
        {"en": "i"},
        "unit.J",
        "symbol.theoretical_indicated_work",
        html="<i>L</i><sub>i</sub>′",
    ),
    "piston_velocity_max": Symbol("v", {"en": "max"}, "unit.m_s", "symbol.piston_velocity_max"),
    "piston_acceleration_max": Symbol(
        "j", {"en": "max"}, "unit.m_s2", "symbol.piston_acceleration_max"
    ),
    # the two-term formula's acceleration less the exact one (the kinematics figure's lowest graph)
    "piston_acceleration_error": Symbol(
        "j",
        {"en": "p", "uk": "п", "ru": "п"},
        "unit.m_s2",
        "symbol.piston_acceleration_error",
        html="Δ<i>j</i><sub>{sub}</sub>",
    ),
    "piston_acceleration_min": Symbol(
        "j", {"en": "min"}, "unit.m_s2", "symbol.piston_acceleration_min"
    ),
    "cylinder_crank_angle": Symbol(
        "α", {"en": "i"}, "°", "symbol.cylinder_crank_angle", html="<i>α</i><sub><i>i</i></sub>"
    ),
    "cycle_delay": Symbol(
        "α", {"en": "0i"}, "°", "symbol.cycle_delay", html="Δ<i>α</i><sub>0<i>i</i></sub>"
    ),
    "accumulated_work": Symbol("W", {}, "unit.J", "symbol.accumulated_work"),
    "excess_work": Symbol("L", {}, "unit.J", "symbol.excess_work", html="Δ<i>L</i>"),
    "reduced_inertia": Symbol("J", {}, "unit.kg_m2", "symbol.reduced_inertia"),
    "angular_velocity_max": Symbol("ω", {"en": "max"}, "unit.rad_s", "symbol.angular_velocity_max"),
    "angular_velocity_min": Symbol("ω", {"en": "min"}, "unit.rad_s", "symbol.angular_velocity_min"),
    "rim_stress": Symbol("σ", {}, "unit.MPa", "symbol.rim_stress"),
    "tensile_strength": Symbol(
        "σ", {"en": "u", "uk": "в", "ru": "в"}, "unit.MPa", "symbol.tensile_strength"
    ),
    "kinetic_energy": Symbol("E", {}, "unit.J", "symbol.kinetic_energy"),
    "initial_energy": Symbol("E", {"en": "0"}, "unit.J", "symbol.initial_energy"),
    "cycle_angle": Symbol("Φ", {}, "", "symbol.cycle_angle", html="Φ"),
    "piston_transfer": Symbol("s", {}, "unit.m_rad", "symbol.piston_transfer", html="<i>s</i>′"),
    "piston_transfer_derivative": Symbol(
        "s", {}, "unit.m_rad2", "symbol.piston_transfer_derivative", html="<i>s</i>″"
    ),
    "inertia_derivative": Symbol(
        "J", {}, "unit.kg_m2_rad", "symbol.inertia_derivative", html="<i>J</i>′"
    ),
    "inertia_torque": Symbol("M", {"en": "j"}, "unit.Nm", "symbol.inertia_torque"),
    "nominal_angular_velocity": Symbol(
        "ω", {"en": "n"}, "unit.rad_s", "symbol.nominal_angular_velocity"
    ),
    "gas_excess_work": Symbol(
        "W", {"en": "g", "uk": "г", "ru": "г"}, "unit.J", "symbol.gas_excess_work"
    ),
    # the running torques of the torque section, as specific tangential forces
    "cylinder_tangential": Symbol(
        "t",
        {"en": "i"},
        "unit.MPa",
        "symbol.cylinder_tangential",
        html="<i>t</i><sub><i>i</i></sub>",
    ),
    "pin_running_tangential": Symbol(
        "t",
        {"en": "wi"},
        "unit.MPa",
        "symbol.pin_running_tangential",
        html="<i>t</i><sub>w<i>i</i></sub>",
    ),
    "journal_running_tangential": Symbol(
        "t",
        {"en": "ki"},
        "unit.MPa",
        "symbol.journal_running_tangential",
        html="<i>t</i><sub>k<i>i</i></sub>",
    ),
    # a single crank carrying several cylinders: its forces are sums over them (not cylinder i's)
    # (the torque section's; the bays section names its own sums over a bay)
    "crank_tangential_total": Symbol(
        "t", {"en": "Σ"}, "unit.MPa", "symbol.crank_tangential_total", sections=SECTION_BOUND
    ),
    "crank_radial_total": Symbol(
        "z", {"en": "Σ"}, "unit.MPa", "symbol.crank_radial_total", sections=SECTION_BOUND
    ),
    "order_force": Symbol(
        "P", {"en": "ν"}, "unit.N", "symbol.order_force", html="<i>P</i><sub><i>ν</i></sub>"
    ),
    # the bearing loads (R alone is the crank radius; R_max, R_mean only in the bearings section)
    "pin_load_max": Symbol(
        "Q", {"en": "max"}, "unit.kN", "symbol.pin_load_max", sections=SECTION_BOUND
    ),
    "pin_load_mean": Symbol(
        "Q",
        {"en": "mean", "uk": "сер", "ru": "ср"},
        "unit.kN",
        "symbol.pin_load_mean",
        sections=SECTION_BOUND,
    ),
    "bearing_pressure_max": Symbol(
        "p", {"en": "max"}, "unit.MPa", "symbol.bearing_pressure_max", sections=SECTION_BOUND
    ),
    "bearing_pressure_mean": Symbol(
        "p",
        {"en": "mean", "uk": "сер", "ru": "ср"},
        "unit.MPa",
        "symbol.bearing_pressure_mean",
        sections=SECTION_BOUND,
    ),
    "journal_load_max": Symbol(
        "R", {"en": "max"}, "unit.kN", "symbol.journal_load_max", sections=SECTION_BOUND
    ),
    "journal_load_mean": Symbol(
        "R",
        {"en": "mean", "uk": "сер", "ru": "ср"},
        "unit.kN",
        "symbol.journal_load_mean",
        sections=SECTION_BOUND,
    ),
    # the balancing section's complex-amplitude model (j, upright, is the imaginary unit there; i numbers
    # the cylinders; ν is the order of a harmonic, as in the torsion section: n is the crank speed)
    "harmonic_order": Symbol("ν", {}, "", "symbol.harmonic_order", sections=SECTION_BOUND),
    "shaft_angle": Symbol(
        "θ", {}, "°", "symbol.shaft_angle", in_scripts=True, sections=SECTION_BOUND
    ),
    "forward_vector": Symbol(
        "f", {"en": "ν"}, "unit.N", "symbol.forward_vector", html="<i>f</i><sub><i>ν</i></sub>"
    ),
    "backward_vector": Symbol(
        "b", {"en": "ν"}, "unit.N", "symbol.backward_vector", html="<i>b</i><sub><i>ν</i></sub>"
    ),
    "backward_conjugate": Symbol(
        "b",
        {"en": "ν"},
        "unit.N",
        "symbol.backward_conjugate",
        html="<i>b</i><sub><i>ν</i></sub><sup>*</sup>",
    ),  # (b̄: the bar crossed the ascender)
    "crank_lag": Symbol(
        "ξ",
        {"en": "i"},
        "°",
        "symbol.crank_lag",
        html="<i>ξ</i><sub><i>i</i></sub>",
        sections=SECTION_BOUND,
    ),
    "cylinder_axis_angle": Symbol(
        "φ",
        {"en": "i"},
        "°",
        "symbol.cylinder_axis_angle",
        html="<i>φ</i><sub><i>i</i></sub>",
        sections=SECTION_BOUND,
    ),
    "cylinder_phase": Symbol(
        "φ",
        {"en": "i"},
        "°",
        "symbol.cylinder_phase",
        html="<i>φ</i><sub><i>i</i></sub>",
        sections=SECTION_BOUND,
    ),
    "cylinder_position": Symbol(
        "x",
        {"en": "i"},
        "unit.mm",
        "symbol.cylinder_position",
        html="<i>x</i><sub><i>i</i></sub>",
        sections=SECTION_BOUND,
    ),
    "cylinder_order_force": Symbol(
        "P",
        {"en": "νi"},
        "unit.N",
        "symbol.cylinder_order_force",
        html="<i>P</i><sub><i>ν</i><i>i</i></sub>",
    ),
    "order_moment": Symbol(
        "M", {"en": "ν"}, "unit.Nm", "symbol.order_moment", html="<i>M</i><sub><i>ν</i></sub>"
    ),
    # a bay's dynamically equivalent model (the textbook's figures 29-33): its rotating vectors and
    # the semi-axes of its hodographs, first and second order
    "bay_forward_first": Symbol(
        "F", {}, "unit.N", "symbol.bay_forward_first", sections=SECTION_BOUND
    ),
    "bay_backward_first": Symbol(
        "P", {}, "unit.N", "symbol.bay_backward_first", sections=SECTION_BOUND
    ),
    "bay_forward_second": Symbol(
        "K", {}, "unit.N", "symbol.bay_forward_second", sections=SECTION_BOUND
    ),
    "bay_backward_second": Symbol(
        "Z", {}, "unit.N", "symbol.bay_backward_second", sections=SECTION_BOUND
    ),
    "bay_semi_axis_x_first": Symbol(
        "a", {"en": "e,I"}, "unit.N", "symbol.bay_semi_axis_x_first", sections=SECTION_BOUND
    ),
    "bay_semi_axis_y_first": Symbol(
        "b", {"en": "e,I"}, "unit.N", "symbol.bay_semi_axis_y_first", sections=SECTION_BOUND
    ),
    "bay_semi_axis_x_second": Symbol(
        "a", {"en": "e,II"}, "unit.N", "symbol.bay_semi_axis_x_second", sections=SECTION_BOUND
    ),
    "bay_semi_axis_y_second": Symbol(
        "b", {"en": "e,II"}, "unit.N", "symbol.bay_semi_axis_y_second", sections=SECTION_BOUND
    ),
    "hodograph_semi_axis_x": Symbol("a", {"en": "e"}, "unit.N", "symbol.hodograph_semi_axis_x"),
    "hodograph_semi_axis_y": Symbol("b", {"en": "e"}, "unit.N", "symbol.hodograph_semi_axis_y"),
    "cylinder_spacing": Symbol(
        "a", {}, "unit.mm", "symbol.cylinder_spacing", sections=SECTION_BOUND
    ),
    # the bearings section's vectors (bold) and spans
    "pin_load_vector": Symbol(
        "q",
        {"en": "pin", "uk": "ш.ш", "ru": "ш.ш"},
        "unit.MPa",
        "symbol.pin_load_vector",
        html="<b><i>q</i></b><sub>{sub}</sub>",
    ),
    "rod_bearing_load_vector": Symbol(
        "q",
        {"en": "bearing", "uk": "ш.п", "ru": "ш.п"},
        "unit.MPa",
        "symbol.rod_bearing_load_vector",
        html="<b><i>q</i></b><sub>{sub}</sub>",
    ),
    "rotation_matrix": Symbol("Π", {}, "", "symbol.rotation_matrix", html="<b>Π</b>"),
    "journal_load_vector": Symbol(
        "R",
        {"en": "i,i+1"},
        "unit.MPa",
        "symbol.journal_load_vector",
        html="<b><i>R</i></b><sub><i>i</i>,<i>i</i>+1</sub>",
    ),
    "crank_force_vector": Symbol(
        "F",
        {"en": "i"},
        "unit.MPa",
        "symbol.crank_force_vector",
        html="<b><i>F</i></b><sub><i>i</i></sub>",
    ),
    "crank_t_unit_vector": Symbol(
        "e",
        {"en": "t,i"},
        "",
        "symbol.crank_t_unit_vector",
        html="<b>e</b><sub><i>t</i>,<i>i</i></sub>",
    ),
    "crank_z_unit_vector": Symbol(
        "e",
        {"en": "z,i"},
        "",
        "symbol.crank_z_unit_vector",
        html="<b>e</b><sub><i>z</i>,<i>i</i></sub>",
    ),
    "cylinder_radial": Symbol(
        "z", {"en": "i"}, "unit.MPa", "symbol.cylinder_radial", html="<i>z</i><sub><i>i</i></sub>"
    ),
    "crank_span": Symbol(
        "l", {"en": "i"}, "unit.mm", "symbol.crank_span", html="<i>l</i><sub><i>i</i></sub>"
    ),
    "span_before": Symbol(
        "l", {"en": "i"}, "unit.mm", "symbol.span_before", html="<i>l</i>′<sub><i>i</i></sub>"
    ),
    "span_after": Symbol(
        "l", {"en": "i"}, "unit.mm", "symbol.span_after", html="<i>l</i>″<sub><i>i</i></sub>"
    ),
    # the flywheel's rim and the accumulated work's extremes
    "accumulated_work_max": Symbol("W", {"en": "max"}, "unit.J", "symbol.accumulated_work_max"),
    "accumulated_work_min": Symbol("W", {"en": "min"}, "unit.J", "symbol.accumulated_work_min"),
    "rim_mass": Symbol("m", {}, "unit.kg", "symbol.rim_mass", sections=SECTION_BOUND),
    "rim_width": Symbol("b", {}, "unit.mm", "symbol.rim_width", sections=SECTION_BOUND),
    "rim_height": Symbol("h", {}, "unit.mm", "symbol.rim_height", sections=SECTION_BOUND),
    # the error study (numerics)
    "relative_error": Symbol(
        "ε", {"en": "X"}, "", "symbol.relative_error", html="<i>ε</i><sub><i>X</i></sub>"
    ),
    "studied_value": Symbol("X", {}, "", "symbol.studied_value", sections=SECTION_BOUND),
    # the grid's step: the given data's table and the error study write it (Δα has no other meaning)
    "angle_step": Symbol("α", {}, "°", "symbol.angle_step", html="Δ<i>α</i>"),
    "total_torque": Symbol("M", {}, "unit.Nm", "symbol.total_torque", sections=SECTION_BOUND),
    "reference_torque": Symbol(
        "M", {"en": "ref", "uk": "ет", "ru": "эт"}, "unit.Nm", "symbol.reference_torque"
    ),
    "reference_work": Symbol(
        "L", {"en": "ref", "uk": "ет", "ru": "эт"}, "unit.J", "symbol.reference_work"
    ),
    "series_displacement": Symbol(
        "s",
        {"en": "N"},
        "unit.mm",
        "symbol.series_displacement",
        html="<i>s</i><sub><i>N</i></sub>",
    ),
    "series_term": Symbol("k", {}, "", "symbol.series_term", sections=SECTION_BOUND),
    # the error table's columns (the relative error of each) and the kinematics forms' differences
    "tangential_max": Symbol(
        "t", {"en": "max"}, "unit.MPa", "symbol.tangential_max", sections=SECTION_BOUND
    ),
    "tangential_min": Symbol(
        "t", {"en": "min"}, "unit.MPa", "symbol.tangential_min", sections=SECTION_BOUND
    ),
    "crank_load_max": Symbol(
        "q", {"en": "max"}, "unit.MPa", "symbol.crank_load_max", sections=SECTION_BOUND
    ),
    "displacement_difference": Symbol(
        "s",
        {},
        "unit.m",
        "symbol.displacement_difference",
        html="Δ<i>s</i>",
        sections=SECTION_BOUND,
    ),
    "acceleration_difference": Symbol(
        "j",
        {},
        "unit.m_s2",
        "symbol.acceleration_difference",
        html="Δ<i>j</i>",
        sections=SECTION_BOUND,
    ),
    "power_series_coefficient": Symbol(
        "c", {"en": "k"}, "", "symbol.power_series_coefficient", html="<i>c</i><sub><i>k</i></sub>"
    ),
    "fourier_series_coefficient": Symbol(
        "H",
        {"en": "k"},
        "",
        "symbol.fourier_series_coefficient",
        html="<i>H</i><sub><i>k</i></sub>",
    ),
    # the given data and the indicator diagram's tables
    "strokes": Symbol("τ", {}, "", "symbol.strokes"),
    # not τ alone, which is the number of strokes
    "ignition_delay_time": Symbol(
        "τ", {"en": "i", "uk": "з", "ru": "з"}, "unit.ms", "symbol.ignition_delay_time"
    ),
    # the balancing means: Q = F + ΣC
    "counterweight_force": Symbol("Q", {}, "unit.N", "symbol.counterweight_force"),
    # the sums over all cranks and cylinders (a letter after Σ is the sum, not one crank's quantity);
    # a sum of one order is printed with the order in Roman numerals (ΣP_VI: one ΣP_ν)
    "sum_centrifugal": Symbol("C", {}, "unit.N", "symbol.sum_centrifugal", html="Σ<i>C</i>"),
    "sum_centrifugal_moment": Symbol(
        "M", {"en": "C"}, "unit.Nm", "symbol.sum_centrifugal_moment", html="Σ<i>M</i><sub>C</sub>"
    ),
    "sum_order_force": Symbol(
        "P", {"en": "ν"}, "unit.N", "symbol.sum_order_force", html="Σ<i>P</i><sub><i>ν</i></sub>"
    ),
    "sum_order_moment": Symbol(
        "M", {"en": "ν"}, "unit.Nm", "symbol.sum_order_moment", html="Σ<i>M</i><sub><i>ν</i></sub>"
    ),
    # the flywheel's given irregularity, [δ]
    "allowed_irregularity": Symbol("δ", {}, "", "symbol.allowed_irregularity", html="[<i>δ</i>]"),
    "residual_gas_pressure": Symbol("p", {"en": "r"}, "unit.MPa", "symbol.residual_gas_pressure"),
    "rounded_max_pressure": Symbol("p", {"en": "z′"}, "unit.MPa", "symbol.rounded_max_pressure"),
    "rounded_tdc_pressure": Symbol("p", {"en": "c″"}, "unit.MPa", "symbol.rounded_tdc_pressure"),
    "theoretical_pressure": Symbol("p", {"en": "theor"}, "unit.MPa", "symbol.theoretical_pressure"),
}


class SymbolTable(Mapping[str, Symbol]):
    """A report's symbol table: key -> :class:`~crankdyn.plugin.types.Symbol`, in order, never
    changed after it is made. Equal (and hashed) by its contents, so what is built from a table
    (the subscript maps, the "where" lines' patterns) is kept per table's contents, and a run
    with other plugins' symbols never reads another run's."""

    __slots__ = ("_symbols", "_contents")

    def __init__(self, symbols: Mapping[str, Symbol]):
        self._symbols = dict(symbols)
        self._contents = repr(list(self._symbols.items()))

    def __getitem__(self, key: str) -> Symbol:
        return self._symbols[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._symbols)

    def __len__(self) -> int:
        return len(self._symbols)

    def __hash__(self) -> int:
        return hash(self._contents)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SymbolTable) and other._contents == self._contents

    def __repr__(self) -> str:
        return f"SymbolTable({len(self)} symbols)"


#: The core's symbols: the quantities many sections share (see above).
SYMBOLS = SymbolTable(_CORE_SYMBOLS)
_STAGE_SYMBOL_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def symbol_table(stages: Iterable) -> SymbolTable:
    """The symbol table of a run: the core's :data:`SYMBOLS` and the symbols ``stages`` declare
    (``StagePresentation.symbols``): key ``k`` of stage ``s`` as ``s.k`` (meaning: the catalog key
    ``symbol.s.k``), read in the stage's own section unless the symbol names its ``sections``.
    Built from the registry's stages for each report; a stage not in a report's plan adds nothing
    to it (its section is absent). A plugin's key that is not an identifier is a
    :class:`~crankdyn.errors.PluginError`."""
    stages = list(stages)
    table = dict(_CORE_SYMBOLS)
    table.update(_section_bound(stages))
    for stage in stages:
        look = stage.presentation
        for key, symbol in (look.symbols if look is not None else {}).items():
            if not _STAGE_SYMBOL_KEY.fullmatch(key) or not isinstance(symbol, Symbol):
                raise PluginError(
                    f"stage {stage.name!r}: symbol {key!r} must be an identifier mapped "
                    "to a crankdyn.plugin.types.Symbol"
                )
            table[f"{stage.name}.{key}"] = (
                symbol if symbol.sections else replace(symbol, sections=(stage.name,))
            )
    return SymbolTable(
        {key: symbol for key, symbol in table.items() if symbol.sections != SECTION_BOUND}
    )


def _section_bound(stages: list) -> dict[str, Symbol]:
    """The core's :data:`SECTION_BOUND` symbols with the sections of the stages that declare them
    (``StagePresentation.section_symbols``); one that is not such a symbol is a :class:`PluginError`."""
    declaring: dict[str, list[str]] = {}
    for stage in stages:
        for key in stage.presentation.section_symbols if stage.presentation is not None else ():
            symbol = _CORE_SYMBOLS.get(key)
            if symbol is None or symbol.sections != SECTION_BOUND:
                raise PluginError(
                    f"stage {stage.name!r}: {key!r} in section_symbols is not one of the core's "
                    "section-bound symbols (typeset.SECTION_BOUND)"
                )
            declaring.setdefault(key, []).append(stage.name)
    return {
        key: replace(_CORE_SYMBOLS[key], sections=tuple(names)) for key, names in declaring.items()
    }


#: Subscript words written in English in the code, for any base letter (``p_mean``, ``M_exact``).
SUBSCRIPT_WORDS: dict[str, dict[str, str]] = {
    "mean": {"uk": "сер", "ru": "ср"},
    "theor": {"uk": "теор", "ru": "теор"},
    "exact": {"uk": "точн", "ru": "точн"},
    "bearing": {"uk": "ш.п", "ru": "ш.п"},
    "pin": {"uk": "ш.ш", "ru": "ш.ш"},
    "ref": {"uk": "ет", "ru": "эт"},  # a reference value (M_ref, L_ref of the error study)
}


def symbol_sub(key: str, language: str, symbols: SymbolTable = SYMBOLS) -> str:
    """The subscript of symbol ``key`` in ``language`` (English if the language has none; "" for none)."""
    sub = symbols[key].sub
    return sub.get(language, sub.get("en", ""))


def symbol_html(key: str, language: str, symbols: SymbolTable = SYMBOLS) -> str:
    """``<i>s</i><sub>п</sub>``: the symbol as HTML markup."""
    s = symbols[key]
    sub = symbol_sub(key, language, symbols)
    if s.html:
        return s.html.replace("{sub}", sub)
    return f"<i>{s.base}</i><sub>{sub}</sub>" if sub else f"<i>{s.base}</i>"


#: Marks after a symbol that make it another quantity (a primed p_i′ is not p_i).
PRIMES = ("′", "″")


@dataclass(frozen=True)
class SymbolFinder:
    """Where a symbol's markup stands for that symbol: not after a Δ or Σ (ΔL is a difference,
    not L, unless the symbol is the Δ one) nor after any text of ``not_after``; not followed by
    a prime (p_i′ is another quantity); a symbol without a subscript not followed by one (ω is
    not ω_ш); not in brackets of its own ([δ] is an allowed value, "[λ_p(ρ − 1) …]" is the
    quantity). Plain string searches: the report looks for some 200 symbols, and a regular
    expression each cost more to compile than the searches take."""

    markup: str
    before: tuple[str, ...]
    bracketed: bool  # whether "[markup]" may be the quantity (a symbol written with brackets)
    subscripted: bool

    def positions(self, text: str) -> Iterator[int]:
        """The start of each occurrence of the symbol in ``text``, left to right, none
        overlapping."""
        markup, size = self.markup, len(self.markup)
        start = text.find(markup)
        while start >= 0:
            end = start + size
            if (
                any(text.endswith(sign, 0, start) for sign in self.before)
                or text.startswith(PRIMES, end)
                or (not self.subscripted and text.startswith("<sub>", end))
                or (
                    not self.bracketed
                    and text.endswith("[", 0, start)
                    and text.startswith("]", end)
                )
            ):
                start = text.find(markup, start + 1)
                continue
            yield start
            start = text.find(markup, end)

    def found_in(self, text: str) -> bool:
        return next(self.positions(text), None) is not None


def symbol_finder(
    key: str, language: str, not_after: tuple[str, ...] = (), symbols: SymbolTable = SYMBOLS
) -> SymbolFinder:
    """The :class:`SymbolFinder` of symbol ``key``'s markup, also not after any of ``not_after``."""
    markup = symbol_html(key, language, symbols)
    # after Δ a difference, after Σ a sum: other quantities
    before = (*not_after, *(sign for sign in ("Δ", "Σ") if not markup.startswith(sign)))
    return SymbolFinder(markup, before, markup.startswith("["), "<sub>" in markup)


#: A subscript index shifted by one (``l″_{i+1}``, ``t_{k(i−1)}``): the same quantity as at index i.
_SHIFTED_INDEX = re.compile(r"<sub>([^<(]*)\(?<i>([a-z])</i>[+−]1\)?</sub>")


def unshifted_indices(html: str) -> str:
    """``html`` with each subscript index shifted by one written as the index itself (``l″_{i+1}``
    read as ``l″_i``, ``t_{k(i−1)}`` as ``t_{ki}``): the symbol the table defines at index i."""
    return (
        _SHIFTED_INDEX.sub(r"<sub>\1<i>\2</i></sub>", html)
        if "1</sub>" in html or "1)</sub>" in html
        else html
    )


#: A force or moment of one order, the order in Roman numerals (ΣP_VI, ΣM_II, P_IV, C_VI): the
#: symbol of order ν (C_I and C_II, the first two orders' amplitudes, are symbols of their own).
_ROMAN = r"(?=[IVX])X{0,3}(?:IX|IV|V?I{0,3})"
_ORDER_INDEX = re.compile(rf"(Σ?<i>[PM]</i>|<i>C</i>(?!<sub>II?</sub>))<sub>{_ROMAN}</sub>")


def order_indices(html: str) -> str:
    """``html`` with each force or moment of one order written as the symbol of order ν (ΣP_VI as
    ΣP_ν, which the list of symbols explains)."""
    if "</i><sub>" not in html:
        return html
    return _ORDER_INDEX.sub(r"\1<sub><i>ν</i></sub>", html)


_STAGE_START = re.compile(r'<section\b[^>]*\bdata-stage="([^"]*)"')


def _stage_parts(html: str) -> list[tuple[str, str]]:
    """(stage, text) of ``html`` in order: a part runs from a section's start to the next section's
    start (as the "where" lines read a report, equation_legend); the part before the first is ""."""
    starts = list(_STAGE_START.finditer(html))
    parts = [("", html[: starts[0].start()] if starts else html)]
    for m, after in zip(starts, starts[1:] + [None], strict=True):
        parts.append((m.group(1), html[m.start() : after.start() if after else len(html)]))
    return parts


def sections_taking_over(symbols: SymbolTable, language: str) -> dict[str, set[str]]:
    """markup -> the sections where a symbol of ``symbols`` with that markup and its own
    ``sections`` is read: there a symbol of all sections with the same markup is not."""
    taken_over: dict[str, set[str]] = {}
    for key, symbol in symbols.items():
        if symbol.sections:
            taken_over.setdefault(symbol_html(key, language, symbols), set()).update(
                symbol.sections
            )
    return taken_over


def symbols_used(html: str, language: str, symbols: SymbolTable = SYMBOLS) -> list[str]:
    """The keys of ``symbols`` whose markup the (typeset) report ``html`` shows, in alphabetical order.
    A symbol without a subscript counts only where no subscript follows it (``<i>ω</i>`` is the
    crank's angular velocity, ``<i>ω</i><sub>ш</sub>`` the rod's); a shifted index counts as the
    index (:func:`unshifted_indices`). A symbol of some sections counts only where it is read: in
    those sections; one of all sections not in the sections where one of the same markup takes
    over (the vane engine's μ is not the torque non-uniformity, the rod dynamics' M not the error
    study's total torque). A stage's own symbol (``stage.key``) exists only in a report that has the
    stage's section (the vane engine's S of the input table is not a piston engine's)."""
    parts = _stage_parts(order_indices(unshifted_indices(html)))
    present = {stage for stage, _ in parts}
    table = SymbolTable(
        {
            key: symbol
            for key, symbol in symbols.items()
            if "." not in key or key.split(".", 1)[0] in present
        }
    )
    taken_over = sections_taking_over(table, language)
    texts: dict[tuple[bool, frozenset[str]], str] = {}
    used = []
    for key, symbol in table.items():
        # (True, sections): the text of those sections; (False, sections): the text outside them
        scope = (
            (True, frozenset(symbol.sections))
            if symbol.sections
            else (False, frozenset(taken_over.get(symbol_html(key, language, table), ())))
        )
        if scope not in texts:
            texts[scope] = "".join(text for stage, text in parts if (stage in scope[1]) == scope[0])
        text = texts[scope]
        # most symbols are not in a report: a plain search for the markup spares their patterns
        if not text or symbol_html(key, language, table) not in text:
            continue
        # a primed letter (z′_B, p_i′) is another quantity, as the where-lines read it
        if _finder(key, language, table).found_in(text):
            used.append(key)
    return sorted(used, key=lambda k: _alphabetical(k, language, table))


@functools.lru_cache(maxsize=4096)
def _finder(key: str, language: str, symbols: SymbolTable) -> SymbolFinder:
    """A symbol's finder made once a process (a table is hashed by its contents)."""
    return symbol_finder(key, language, symbols=symbols)


def _alphabetical(key: str, language: str, symbols: SymbolTable) -> tuple:
    """The list of symbols' order: Latin letters, then Greek, each in its alphabet's order, a
    capital before its small letter, a symbol without subscript before those with one."""
    base = symbols[key].base
    return (not base.isascii(), base.lower(), base.islower(), symbol_sub(key, language, symbols))


def symbol_unit(key: str, t, symbols: SymbolTable = SYMBOLS) -> str:
    """The symbol's unit in the report's language ("" for a ratio)."""
    return unit_text(symbols[key].unit, t)


def unit_text(unit: str, t) -> str:
    """A symbol's unit as printed: a catalog key (``unit.kg``, or a plugin's own such as
    ``speed_fluctuation.unit_N_m_rad``) in the report's language, else the literal (``°``, "")."""
    return t(unit) if "." in unit and " " not in unit and t.has(unit) else unit


def symbol_mathtext(key: str, language: str, symbols: SymbolTable = SYMBOLS) -> str:
    """``$s_{\\mathrm{п}}$``: the symbol as matplotlib mathtext."""
    s = symbols[key]
    return f"${s.base}_{{\\mathrm{{{symbol_sub(key, language, symbols)}}}}}$"


_BASES = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyzαβγδεζηθικλμνξπρστυφχψωΔΣΦ"


@functools.lru_cache(maxsize=16)
def _subscript_map(language: str, symbols: SymbolTable = SYMBOLS) -> dict[tuple[str, str], str]:
    """(base, any language's subscript) -> the subscript in ``language``."""
    out: dict[tuple[str, str], str] = {}
    for word, forms in SUBSCRIPT_WORDS.items():
        for base in _BASES:
            out[(base, word)] = forms.get(language, word)
    for s in symbols.values():
        if not s.sub:
            continue
        target = s.sub.get(language, s.sub["en"])
        for sub in s.sub.values():
            out.setdefault((s.base, sub), target)
    return out


# ----------------------------------------------------------------------------- HTML text
_LETTER = r"A-Za-zΑ-Ωα-ωА-Яа-яІіЇїЄєҐґ"
#: ``s_п``, ``p_z′``, ``l″_i``, ``C_II``, ``λ_p``, ``z̈_A``, ``{..}`` braces for a longer subscript: one base
#: letter (not the tail of a word or an identifier; a combining dot or two above it allowed), its
#: subscript of letters or digits.
_SUB = re.compile(
    rf"(?<![A-Za-zА-Яа-яІіЇїЄєҐґ0-9_])([{_LETTER}][\u0300-\u036f]?)([′″]?)_(\{{[^{{}}]*\}}|[{_LETTER}0-9]+)([′″]?)"
)
#: ``10^−16``, ``cos^2``, ``ω^{2}``: a superscript of an optional sign and digits or letters.
_SUP = re.compile(rf"\^(\{{[^{{}}]*\}}|[−\-]?[0-9{_LETTER}]+)")
_SUB_HTML = re.compile(r"<i>([^<]{1,2})</i>((?:</b>)?)<sub>([^<]+)</sub>")
#: A number written by Python's exponent notation (``1.2e-03``) that slipped through.
_E_NUMBER = re.compile(r"(?<![\w.])([−\-]?\d+(?:[.,]\d+)?)[eE]([+\-−]?)(\d+)(?![\w])")


def _braces(text: str) -> str:
    return text[1:-1] if text.startswith("{") and text.endswith("}") else text


#: A Latin letter standing alone in Cyrillic prose is a quantity's symbol ("координату x", "n-го
#: порядку", "вектори F і P", "d·B"): set in italics as the equations set it (not the same
#: letter upright in the text and italic in the formula). Only between spaces or punctuation inside
#: one text node (a letter beside a tag belongs to a formula's markup: the differential d of
#: "d<i>V</i>"); not an initial ("Khurmi R. S.": a capital before a full stop after a name), the
#: Roman numeral I (V and X are the volume and a studied value), the upright imaginary unit j
#: ("j – уявна одиниця", "j sin α") or Euler's e ("e^{jα}").
_LETTER_BEFORE = r"(?<=[\s(\[«„“–—·=+−,|/ΣΔ\u00a0\u202f\u2060])([A-HJ-Za-z])"
_LETTER_AFTER = r"[\s,.;:!?)\]»”–—·=+−/|\u00a0\u202f\u2060′″α-ωΑ-Ω]|-[а-яіїєґ]"
#: What follows the imaginary unit j in prose, where it is set upright: its definition ("j –
#: уявна одиниця"), a product ("j sin α") or a remark in brackets.
_IMAGINARY_UNIT_NEXT = (" (", " sin", " – уявна", " – мнимая", " is the imag")
#: A letter naming a shape ("V-подібного", "V-образного", "W-подібний") is a word, not a symbol.
_SHAPE_WORD = r"(?!-(?:подібн|образн|под))"
_PROSE_LETTER = re.compile(rf"{_LETTER_BEFORE}{_SHAPE_WORD}(?={_LETTER_AFTER})")
#: The same, where the text ends with the letter too (a meaning put in before its unit: "… до радіуса R").
_PROSE_LETTER_AT_END = re.compile(rf"{_LETTER_BEFORE}{_SHAPE_WORD}(?={_LETTER_AFTER}|$)")
#: What follows a letter that _SUB sets with its subscript or exponent.
_SCRIPT_NEXT = re.compile(r"[′″]?[_^]")
_ONE_LETTER = re.compile(r"[A-Za-z]")
_CYRILLIC = re.compile(r"[а-яА-ЯіїєґІЇЄҐёЁ]")
#: Cyrillic-prose languages, whose lone Latin letters are symbols (in English "a" and "I" are words).
_ITALIC_PROSE_LANGUAGES = frozenset({"uk", "ru"})


@functools.lru_cache(maxsize=8)
def _index_subscripts(symbols: SymbolTable = SYMBOLS) -> dict[tuple[str, str], str]:
    """(base, subscript as a catalog writes it) -> the subscript's markup, for the symbols whose
    subscript holds an index in italics (l_i, C_n, Δα_0i, t_wi): the text sets them as the
    equations do (not l′_i upright in the text and italic in formula 7.3). A pair
    that another symbol writes upright (p_i, the indicated pressure) is left as it is."""
    indexed: dict[tuple[str, str], str] = {}
    upright: set[tuple[str, str]] = set()
    for symbol in symbols.values():
        m = re.fullmatch(
            r"(?:Δ)?(?:<b>)?<i>(.)</i>(?:</b>)?[′″]?<sub>(.*?)</sub>[′″]?", symbol.html or ""
        )
        if m and "<i>" in m.group(2):
            indexed[(m.group(1), re.sub(r"<[^>]+>", "", m.group(2)))] = m.group(2)
        elif not symbol.html:
            upright.update((symbol.base, sub) for sub in symbol.sub.values())
    return {pair: markup for pair, markup in indexed.items() if pair not in upright}


def _prose_letter(m: re.Match) -> str:
    letter, text, end = m.group(1), m.string, m.end()
    following = text[end : end + 12]
    preceding = text[
        max(0, m.start() - 40) : m.start()
    ]  # (the words around it: a window, not the whole node)
    if _SCRIPT_NEXT.match(following):
        return letter  # a symbol with a subscript, which _SUB sets whole
    if letter.isupper() and following.startswith(".") and _AFTER_NAME.search(preceding):
        return letter  # an initial: after a capitalised name or another initial ("Khurmi R. S.")
    if letter == "j" and following.startswith(_IMAGINARY_UNIT_NEXT):
        return letter  # the imaginary unit, upright
    before = _LAST_WORD.search(preceding)
    after = _FIRST_WORD.match(following + text[end + 12 : end + 40])
    if (before and _LATIN_WORD.fullmatch(before.group(1))) or (
        after and _LATIN_WORD.fullmatch(after.group(1))
    ):
        return letter  # an article amid Latin words: the student's English title quoted in the note
    return f"<i>{letter}</i>"


_AFTER_NAME = re.compile(r"(?:\b[A-ZА-ЯІЇЄҐ][\w’'-]*\.?)[\s\u00a0]+$")
_LAST_WORD = re.compile(r"([^\W\d_]+)[^\w]*$")
_FIRST_WORD = re.compile(r"[^\w]*([^\W\d_]+)")
_LATIN_WORD = re.compile(r"[A-Za-z]{2,}")


def italic_letters(text: str, language: str, whole: bool = True) -> str:
    """An escaped text with its lone Latin letters in italics, as the report's prose has them (the
    meanings of the list of symbols and of the "where" lines, which are put in after the typesetting).
    ``whole``: the text is all there is (a letter may end it); a document's text node may end with
    a formula's letter before its markup (the d of "d<i>V</i>"), which stays as it is."""
    if language in _ITALIC_PROSE_LANGUAGES and _CYRILLIC.search(text):
        return (_PROSE_LETTER_AT_END if whole else _PROSE_LETTER).sub(_prose_letter, text)
    return text


def typeset_text_html(
    text: str,
    language: str,
    units: list[str],
    decimal: str = ",",
    prose: bool = False,
    symbols: SymbolTable = SYMBOLS,
) -> str:
    """One HTML text node (already escaped) with sub/superscripts, exponents and unit spacing;
    ``prose`` (a node outside any italic, bold, sub- or superscript), in Cyrillic prose a lone Latin
    letter (a symbol) in italics."""
    return _typeset_text(
        text,
        language,
        units,
        decimal,
        prose,
        _subscript_map(language, symbols),
        _index_subscripts(symbols),
    )


def _typeset_text(
    text: str,
    language: str,
    units: list[str],
    decimal: str,
    prose: bool,
    subs: dict[tuple[str, str], str],
    indices: dict[tuple[str, str], str],
) -> str:
    """:func:`typeset_text_html` with the symbol table's subscript maps looked up once by the
    caller (a document has thousands of text nodes)."""

    def sub(m: re.Match) -> str:
        base, prime, s, prime2 = m.group(1), m.group(2), _braces(m.group(3)), m.group(4)
        s = indices.get((base, s)) or subs.get((base, s), s)
        return f"<i>{base}</i>{prime}<sub>{s}</sub>{prime2}"

    def e_number(m: re.Match) -> str:
        sign = "⁻" if m.group(2) in ("-", "−") else ""
        digits = str(int(m.group(3))).translate(str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹"))
        mantissa = m.group(1).replace("-", MINUS).replace(".", decimal)
        return f"{mantissa}·10{sign}{digits}"

    text = _E_NUMBER.sub(e_number, text)
    if (
        prose
    ):  # (a text in Latin letters only, as an English title a student typed, is no Cyrillic prose)
        text = italic_letters(text, language, whole=False)
    text = _SUB.sub(sub, text)
    text = _SUP.sub(lambda m: f"<sup>{_braces(m.group(1)).replace('-', MINUS)}</sup>", text)
    if units:
        text = _unit_spacing(text, units)
    return text


#: "p_z = 6 МПа", "α = 464°": a quantity and its value are not parted at the line's end (ДСТУ 3008
#: would repeat the sign on the next line, which HTML cannot): no-break spaces around "=" when a
#: number follows it.
_EQUALS_NUMBER = re.compile(r" = (?=[−\-+]?\d|\|)")
#: "м/с²", "ΣM/(C·a)": no line break after a slash inside a word or formula (a web address keeps
#: its breaks: it has no other place to break; the slash of a closing tag the sub/superscripts
#: put in is no slash of the text).
_SLASH_IN_WORD = re.compile(r"(?<![\s<])/(?=[^\s/>\u2060])")
WORD_JOINER = "\u2060"
#: "C_n = |A_n|·C_I": no line break after the opening bar of an absolute value (Unicode lets a
#: line break after "|", which would leave "C_n = |" at a line's end).
_OPENING_BAR = re.compile(r"(?:(?<=[\s(\u00a0=·])|^)\|(?=[^\s|\u2060]|$)")
#: "Петров В. М.", "Khurmi R. S.", "Петров В.М.": a surname and its initials stay on one line (the
#: title page would otherwise break "Петров В. /М."): a no-break space before a capital
#: initial after a word or an initial, and ("В. М. Петров") after an initial before a capitalised word.
_BEFORE_INITIAL = re.compile(
    r"(?<=[^\W\d_]|\.) (?=[A-ZА-ЯІЇЄҐЁ]\.(?:[A-ZА-ЯІЇЄҐЁ]\.)*(?:[\s,;:)]|$))"
    r"|(?<=\b[A-ZА-ЯІЇЄҐЁ]\.) (?=[A-ZА-ЯІЇЄҐЁ][a-zа-яіїєґё'’])"
)


#: "табл. 2.1", "рис. Б.3", "с. 45", "розд. 6": an abbreviated reference and its number stay on one
#: line (ДСТУ 3008 binds them; a line starting with the bare "6.3)" reads as a decimal fraction).
_REFERENCE_NUMBER = re.compile(
    r"(?<![^\W\d_])(табл|рис|розд|підрозд|разд|подразд|дод|прил|с|ст|п)\. "
    r"(?=\d|[A-ZА-ЯІЇЄҐ]\.\d)"
)


#: A capital Latin letter and a hyphen opening a word ("V-образного", "W-подібного", "V-twin"):
#: a line would otherwise end with the lone letter and its hyphen.
_LETTER_HYPHEN = re.compile(r"(?<![\w-])([A-Z])-(?=[^\W\d_])")


#: An engine's designation by its cylinders and D/S in cm ("6ЧН 8,4/8,96", "4Ch 8.2/7.8"):
#: the letters and the bore/stroke are one name, kept on one line.
_DESIGNATION = re.compile(r"(?<!\w)(\d*(?:Ч|Ch|Д)[A-ZА-ЯҐЄІЇ]{0,3}) (?=\d+(?:[,.]\d+)?/\d)")


def _unbreakable(text: str) -> str:
    if "/" in text:
        text = _DESIGNATION.sub("\\1\u00a0", text)
    if "-" in text:
        text = _LETTER_HYPHEN.sub("\\1-" + WORD_JOINER, text)
    text = _EQUALS_NUMBER.sub("\u00a0=\u00a0", text)
    if "|" in text:
        text = _OPENING_BAR.sub("|" + WORD_JOINER, text)
    if "/" in text and "://" not in text and "www." not in text:
        text = _SLASH_IN_WORD.sub("/" + WORD_JOINER, text)
    if ". " in text:
        text = _BEFORE_INITIAL.sub("\u00a0", text)
        text = _REFERENCE_NUMBER.sub("\\1.\u00a0", text)
    return text


def _unit_spacing(text: str, units: list[str]) -> str:
    return _unit_pattern(tuple(units)).sub(lambda m: f"{m.group(1)}{NARROW_NBSP}{m.group(2)}", text)


@functools.lru_cache(maxsize=16)
def _unit_pattern(units: tuple[str, ...]) -> re.Pattern:
    """A number (its last digit, or the superscript exponent of ``3,0·10⁻⁵``), a space and one of
    ``units`` (longest first): built once per unit list, not for each of a report's text nodes."""
    alternatives = "|".join(re.escape(u) for u in sorted(units, key=len, reverse=True))
    return re.compile(rf"([\d⁰¹²³⁴⁵⁶⁷⁸⁹])[ \u00a0]({alternatives})(?![{_LETTER}])")


_TAG = re.compile(r"(<[^>]+>)")


def unbreakable_html(html: str) -> str:
    """The document with no line break between a quantity and its value ("p_z = 6 МПа") nor after
    a slash inside a word or formula ("м/с²"), an absolute value's opening bar or the hyphen of
    "V-образный", in every text node (the last pass over the report:
    the equations' legends and the list of symbols included)."""
    parts = _TAG.split(html)
    skip = 0
    for i, part in enumerate(parts):
        if i % 2 == 1:
            if part[1:2] in _SKIP_FIRST:  # most tags cannot open or close a skipped element
                skip = _skip_depth(part, skip)
        elif not skip and (
            "=" in part or "/" in part or ". " in part or "|" in part or "-" in part
        ):
            parts[i] = _unbreakable(part)
    return "".join(parts)


_SKIP_FIRST = frozenset("sStT/")


#: The inline tags a formula's markup is made of: text inside them is no prose.
_INLINE_TAG = re.compile(r"<(/?)(?:i|b|sub|sup)[\s>]")
_INLINE_FIRST = frozenset("ibs/")


def _skip_depth(tag: str, skip: int) -> int:
    """How deep inside ``<style>``, ``<script>`` or ``<title>`` (whose text is not the report's)
    the text after ``tag`` is."""
    if tag[1:2] not in _SKIP_FIRST or (tag[1:2] == "/" and tag[2:3] not in _SKIP_FIRST):
        return skip  # most tags: no need to parse the name (a report has thousands)
    name = tag[1:].split(None, 1)[0].rstrip(">").lower() if len(tag) > 2 else ""
    if name in ("style", "script", "title"):
        return skip + 1
    if name in ("/style", "/script", "/title"):
        return max(skip - 1, 0)
    return skip


def typeset_html(
    html: str, language: str, units: list[str], decimal: str = ",", symbols: SymbolTable = SYMBOLS
) -> str:
    """Apply :func:`typeset_text_html` to every text node of a document (not to tags,
    attribute values, ``<style>``, ``<script>`` or ``<title>``) and give the table headers'
    and equations' ``<i>X</i><sub>Y</sub>`` the language's subscript."""
    subs = _subscript_map(language, symbols)
    indices = _index_subscripts(symbols)
    parts = _TAG.split(html)
    skip = inline = 0  # inside style/script/title; inside an italic, bold, sub- or superscript
    for i, part in enumerate(parts):
        if i % 2 == 1:  # a tag
            if part[1:2] in _SKIP_FIRST:  # most tags cannot open or close a skipped element
                skip = _skip_depth(part, skip)
            if part[1:2] in _INLINE_FIRST and (m := _INLINE_TAG.match(part)):
                inline = max(inline + (-1 if m.group(1) else 1), 0)
            continue
        if skip or not part.strip():
            continue
        if (
            not inline
            and language in _ITALIC_PROSE_LANGUAGES
            and _ONE_LETTER.fullmatch(part)
            and part != "I"  # the Roman numeral of an order's row, as in prose (_LETTER_BEFORE)
            and parts[i - 1].startswith("<td")
        ):
            parts[i] = f"<i>{part}</i>"  # a table cell that is a symbol (the criteria z, t, q)
            continue
        parts[i] = _typeset_text(part, language, units, decimal, not inline, subs, indices)
    out = "".join(parts)
    return _SUB_HTML.sub(
        lambda m: (
            f"<i>{m.group(1)}</i>{m.group(2)}<sub>"
            f"{subs.get((m.group(1), m.group(3)), m.group(3))}</sub>"
        ),
        out,
    )


# ----------------------------------------------------------------------------- figures
def mathtext(text: str, language: str, symbols: SymbolTable = SYMBOLS) -> str:
    """A figure label with ``s_п``/``ω^2`` as matplotlib mathtext (a ``$`` in the text is kept)."""
    if "$" in text or ("_" not in text and "^" not in text):
        return text
    subs = _subscript_map(language, symbols)

    def sub(m: re.Match) -> str:
        base, prime, s, prime2 = m.group(1), m.group(2), _braces(m.group(3)), m.group(4)
        s = subs.get((base, s), s)
        return f"${base}{prime}_{{\\mathrm{{{s}}}}}{prime2}$"

    text = _SUB.sub(sub, text)
    text = _SUP.sub(lambda m: f"$^{{{_braces(m.group(1)).replace('−', '-')}}}$", text)
    return text.replace("$$", "")


def typeset_figure(fig, t, symbols: SymbolTable = SYMBOLS) -> None:
    """Make every text of a matplotlib figure typeset for the report's language: mathtext
    sub/superscripts in labels, titles, legends and annotations, and locale tick labels
    (decimal comma in uk/ru, "−", ×10ⁿ offsets instead of ``1e-03``)."""
    language = t.language
    for ax in fig.get_axes():
        _legend_outside(ax)  # first: the new legend takes its labels from the artists, untypeset
    # the tick locators first: gathering the texts makes each axis's ticks for its locator
    for ax in fig.get_axes():
        for axes in (ax, *ax.child_axes):  # an inset's ticks too (the p–V diagram's pumping loop)
            for axis in (axes.xaxis, axes.yaxis):
                _locale_ticks(axis, t)
    for text in _texts_but_tick_labels(fig):
        value = text.get_text()
        if value and ("_" in value or "^" in value) and "$" not in value:
            text.set_text(mathtext(value, language, symbols))


def _texts_but_tick_labels(fig) -> list:
    """Every Text of ``fig`` (as ``fig.findobj(Text)``) but its ticks' labels: those are numbers,
    written by the axis's formatter each time the figure is drawn (the locale's, above), and
    asking an axis for its ticks would make them now, before the layout sets the limits."""
    from matplotlib.axis import (
        Axis,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )
    from matplotlib.text import (
        Text,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    found, waiting = [], [fig]
    while waiting:
        artist = waiting.pop()
        if isinstance(artist, Text):
            found.append(artist)
        if isinstance(artist, Axis):
            waiting += (artist.label, artist.offsetText)
        else:
            waiting += artist.get_children()
    return found


def _legend_outside(ax) -> None:
    """Move an axes legend above the plotting area, so that it never covers a curve."""
    legend = ax.get_legend()
    if legend is None:
        return
    handles, labels = ax.get_legend_handles_labels()
    if len(labels) != len(legend.get_texts()) or not labels:
        return  # a legend built from its own handles: leave it as its author placed it
    size = legend.get_texts()[0].get_fontsize()
    title = legend.get_title().get_text()  # kept: short labels ("1–2") may need it
    ax.legend(
        handles,
        labels,
        loc="lower right",
        bbox_to_anchor=(1.0, 1.0),
        ncol=_legend_columns(ax, labels, size),
        frameon=False,
        fontsize=size,
        borderaxespad=0.2,
        title=title or None,
        title_fontsize=size,
    )


def _legend_columns(ax, labels, size_pt: float) -> int:
    """As many columns (at most 4) as fit the figure's width: four long labels in one row ("main
    journal after crank 1" …) are wider than the figure, and the layout would squeeze the axes
    into its right half to make room. A label's width is estimated at 0.55 em a character, plus the
    line sample and the gap between columns (about 3 em)."""
    width_pt = ax.figure.get_figwidth() * 72.0 * 0.95
    longest = max(len(label) for label in labels)
    for columns in (4, 3, 2):
        if columns <= len(labels) and columns * (longest * 0.55 + 3.0) * size_pt <= width_pt:
            rows = math.ceil(len(labels) / columns)
            return math.ceil(len(labels) / rows)  # rows filled evenly: 2 + 2, not 3 + 1
    return 1


def _locale_ticks(axis, t) -> None:
    from matplotlib.ticker import (  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
        FuncFormatter,
        LogFormatter,
        ScalarFormatter,
    )

    major = axis.get_major_formatter()
    if type(major) is ScalarFormatter:  # leave custom formatters
        axis.set_major_formatter(locale_formatter(t))
    elif isinstance(
        major, LogFormatter
    ):  # 10⁻³ typeset; minor labels only where no power of ten shows
        axis.set_major_formatter(
            FuncFormatter(lambda x, pos: _log_label(x, t, axis.get_view_interval()))
        )
        axis.set_minor_formatter(
            FuncFormatter(lambda x, pos: _log_minor_label(x, axis.get_view_interval(), t))
        )
        if _decades(axis.get_view_interval()) > _MINOR_TICKS_MAX_DECADES:
            from matplotlib.ticker import (
                NullLocator,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
            )

            # eight unlabelled marks a decade over ten decades are a comb, not a scale (and each
            # mark is a matplotlib tick of five artists: a third of the error study's figure)
            axis.set_minor_locator(NullLocator())


#: A log axis spanning more decades than this has no minor ticks.
_MINOR_TICKS_MAX_DECADES = 5.0


def _decades(view) -> float:
    low, high = sorted(float(v) for v in view)
    return math.log10(high / low) if low > 0 and math.isfinite(high) else 0.0


def _log_minor_label(x: float, view, t) -> str:
    """A log axis's minor tick label where its powers of ten alone leave it (almost) without
    numbers: 2, 3 and 5 times a power of ten when it spans less than a decade (at most one power
    of ten shows), 2 and 5 times one ("5·10⁻²") when it spans less than two (one or two show)."""
    low, high = sorted(float(v) for v in view)
    if low <= 0 or not math.isfinite(high) or high / low >= 100.0 or x <= 0:
        return ""
    exponent = math.floor(math.log10(x) + 1e-9)
    mantissa = x / 10.0**exponent
    if high / low < 10.0:
        return t.number_g(x, 3) if any(abs(mantissa - m) < 1e-6 for m in (2.0, 3.0, 5.0)) else ""
    if any(abs(mantissa - m) < 1e-6 for m in (2.0, 5.0)):
        return (
            t.number_g(x, 3)
            if _plain_numbers(view)
            else f"{int(round(mantissa))}·10{superscript(exponent)}"
        )
    return ""


#: A log axis within these limits is labelled with plain numbers (0,05; 2; 10; 500), as a reader
#: writes them, not as powers of ten ("2·10⁰", "10¹").
PLAIN_LOG_RANGE = (1e-2, 1e4)


def _plain_numbers(view) -> bool:
    low, high = sorted(float(v) for v in view)
    return PLAIN_LOG_RANGE[0] * (1 - 1e-9) <= low and high <= PLAIN_LOG_RANGE[1] * (1 + 1e-9)


def _log_label(x: float, t, view=None) -> str:
    """A log axis's major label: a power of ten as 10⁻³, or a plain number on an axis within
    :data:`PLAIN_LOG_RANGE` (``view``: the axis's limits)."""
    if x <= 0 or not math.isfinite(x):
        return ""
    exponent = math.log10(x)
    if view is not None and _plain_numbers(view):
        return t.number_g(x, 6)
    if abs(exponent - round(exponent)) < 1e-9:
        # Unicode superscripts, as in the tables (1,2·10⁻⁵): real superscripts, and plain text,
        # so no mathtext has to be typeset for each of a log axis's labels
        return f"10{superscript(int(round(exponent)))}"
    return t.number_g(x, 3)


def tick_labels(values, t) -> tuple[list[str], int]:
    """Tick labels in the report's locale, with as few decimals as tell the ticks apart, and
    the power of ten factored out (returned) when the numbers are very large or small."""

    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    big = float(np.max(np.abs(finite))) if finite.size else 0.0
    scale = int(np.floor(np.log10(big))) if big and (big >= 1e6 or big < 1e-2) else 0
    scaled = values / 10.0**scale
    steps = np.diff(np.unique(scaled[np.isfinite(scaled)]))
    step = float(np.min(steps)) if steps.size else 1.0
    decimals = 0
    while decimals < 6 and np.any(np.abs(np.round(scaled, decimals) - scaled) > 1e-6 * step):
        decimals += 1
    return [t.fixed(v, decimals) if np.isfinite(v) else "" for v in scaled], scale


def locale_formatter(t):
    """A matplotlib tick formatter that writes numbers as the report's text does (Babel)."""
    from matplotlib.ticker import (
        Formatter,  # lazy: heavy optional import (matplotlib: only when a figure is drawn)
    )

    class LocaleFormatter(Formatter):
        def __init__(self):
            self.scale = 0
            self._last = ((), [], 0)  # matplotlib asks again for the same ticks at each layout pass

        def format_ticks(self, values):
            key = tuple(float(v) for v in values)
            if key != self._last[0]:
                labels, self.scale = tick_labels(values, t)
                self._last = (key, labels, self.scale)
            else:
                self.scale = self._last[2]
            return list(self._last[1])

        def __call__(self, x, pos=None):
            return tick_labels([x], t)[0][0]

        def get_offset(self):
            return f"×10{superscript(self.scale)}" if self.scale else ""

    return LocaleFormatter()


def journal_name(label: str) -> str:
    """A main journal's identifier ("0-1") as the report prints it: an en dash between the cranks'
    numbers ("0–1"), as a range of numbers is set."""
    return label.replace("-", "\u2013")
