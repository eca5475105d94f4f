"""The kinematic scheme draws a crank's counterweight where the balancing puts it.

An in-line three balances its first-order moment with counterweights on the end cranks, 150° and
210° from their pins (not opposite them). Independent check, written here: the drawn sector's
centroid, seen from the shaft's axis, lies at that angle from the crank pin measured in the
direction of rotation (clockwise on the drawing).
"""

from __future__ import annotations

import math
import re

from conftest import shared_html, shared_run

from crankdyn.report import mechanism_drawing as md


def _clockwise_deg(frm, to) -> float:
    """The angle from direction ``frm`` to ``to``, clockwise, in [0, 360) degrees."""
    a = math.degrees(math.atan2(frm[1], frm[0]) - math.atan2(to[1], to[0]))
    return a % 360.0


def test_the_counterweight_is_drawn_at_the_balancings_angle():
    run = shared_run("inline3-petrol", stages=["balancing", "drawing"])
    fitted = {
        c["crank"]: c["angle_from_crank_deg"]
        for c in run.outputs["balancing"].results["counterweights"]
    }
    assert fitted[1] != 180.0  # the end cranks' counterweights are turned from opposite the pin
    positions = run.outputs["drawing"].artifacts["positions"]
    turned = tuple((k, math.radians(a)) for k, a in fitted.items())
    geometry = type(positions)(
        **{
            **positions.__dict__,
            "counterweight_cranks": tuple(fitted),
            "counterweight_angles": turned,
        }
    )
    outlines = md.counterweights(geometry, 0)
    cranks = [
        (int(name.removeprefix("crank_") or 1) if name != "crank" else 1, b)
        for name, a, b in geometry.links
        if a == "crank_centre" and (name == "crank" or name.removeprefix("crank_").isdigit())
    ]
    drawn = [(k, pin) for k, pin in cranks if k in fitted]
    assert len(outlines) == len(drawn) == 2  # the end cranks', one behind the other in front view
    centre = geometry.joints["crank_centre"][0] * md.MM
    for (k, pin_joint), outline in zip(drawn, outlines, strict=True):
        pin = geometry.joints[pin_joint][0] * md.MM
        sector = outline[1:-1].mean(axis=0)  # the rim's points: their mean lies on the bisector
        assert abs(_clockwise_deg(pin - centre, sector - centre) - fitted[k]) < 1e-6


def test_the_scheme_says_where_a_turned_counterweight_sits():
    html = shared_html("inline3-petrol", None, "ru", ["balancing", "drawing"])
    html = html.linked_html if hasattr(html, "linked_html") else html
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))
    assert "под углом 150,0° от шатунной шейки в направлении вращения" in text
    assert "напротив шатунной шейки – противовес" not in text
    # an engine whose counterweights are opposite their pins keeps the short sentence
    single = shared_html("petrol-1cyl", None, "ru")
    single = single.linked_html if hasattr(single, "linked_html") else single
    assert "Затушёванный сектор напротив шатунной шейки – противовес кривошипа." in re.sub(
        r"\s+", " ", re.sub(r"<[^>]+>", " ", single)
    )
