"""A radial's master cylinder: the balancing section's reciprocating mass against the forces
section's plain m_s, with the slave rods' shares at the master's piston pin worked out here.

Independent reference: each slave rod's rotating part m_sr (1 − κ) and its pin sit at the pin,
a distance r cos γ from the big end along the master rod, so its share at the master's piston
pin is (m_sr (1 − κ) + m_pin) r cos γ / L (Poda 2007, fig. 9); the nine-cylinder radial's pins
lie at γ = 40°·k, k = 1…8, whose cosines sum to −1.
"""

from __future__ import annotations

import html
import math
import re

import pytest
from conftest import shared_html, shared_run

RADIAL = "radial9-aircraft"
#: the example's data: slave rod 1.2 kg with κ = 0.47, pin radius 68 mm, rod 320 mm, no pin mass
SHARE_KG = (
    1.2 * (1 - 0.47) * 0.068 * sum(math.cos(math.radians(40 * k)) for k in range(1, 9)) / 0.320
)
PLAIN_KG = 3.1 + 6.5 * 0.22


def test_the_slave_rods_share_at_the_master_piston_pin_is_worked_out():
    balancing = shared_run(RADIAL).outputs["balancing"].results
    assert SHARE_KG < 0
    assert balancing["slave_pins_master_share_kg"] == pytest.approx(SHARE_KG, rel=1e-9)
    assert balancing["reciprocating_mass_kg"] == pytest.approx(PLAIN_KG + SHARE_KG, rel=1e-9)


@pytest.mark.parametrize(
    "language, said",
    [
        ("en", "The mass ms.m is less than the mass ms = 4.530 kg of section 5"),
        ("ru", "Масса ms.гл меньше массы ms = 4,530 кг раздела 5"),
        ("uk", "Маса ms.гол менша за масу ms = 4,530 кг розділу 5"),
    ],
)
def test_the_balancing_section_says_why_the_master_mass_differs_from_the_forces_section(
    language, said
):
    text = html.unescape(re.sub(r"<[^>]+>", "", shared_html(RADIAL, language=language).linked_html))
    text = re.sub(r"[\u00a0\u202f]", " ", text)
    assert f"{PLAIN_KG:.3f}" == "4.530"
    assert said in text
    pins = f"{SHARE_KG:.3f} kg".replace("-", "−")
    assert (pins if language == "en" else pins.replace(".", ",").replace("kg", "кг")) in text


@pytest.mark.parametrize(
    "language, said",
    [
        ("en", "The slave rods' pins on the master rod take {share} kg off at its piston pin"),
        (
            "ru",
            "Пальцы прицепных шатунов на главном шатуне уменьшают массу у его поршневого пальца на {share} кг",
        ),
    ],
)
def test_the_forces_section_says_its_table_keeps_the_master_rods_own_split(language, said):
    """The forces table was called the master cylinder's while the torque of all cylinders and
    the balancing took the reduced master rod (its slave pins' shares): the section says its
    table keeps the master rod's own split, and by how much the reduced one differs."""
    forces = shared_run(RADIAL).outputs["forces"].results
    assert forces["reciprocating_mass_kg"] == pytest.approx(PLAIN_KG, rel=1e-9)
    assert forces["master_reduced_reciprocating_mass_kg"] == pytest.approx(
        PLAIN_KG + SHARE_KG, rel=1e-9
    )
    page = shared_html(RADIAL, None, language).linked_html
    text = " ".join(html.unescape(re.sub(r"<[^>]+>", "", page)).replace("\u2060", "").split())
    share = f"{abs(SHARE_KG):.3g}".replace(".", "," if language == "ru" else ".")
    assert said.format(share=share) in text
