"""The ``[balancing]`` scene table: the orders balanced and the balancing means chosen."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, ConfigDict

from crankdyn.plugin.contracts import RodOffsetOptions
from crankdyn.scene import quantity as _quantity

ALLOWED_ORDERS = (1, 2, 4, 6, 8, 10, 12)

#: A rotating part only the slave cylinders give (their masses and motion; the cylinders'
#: arrangement cancels it in alike cylinders) is left unbalanced under this share of C_I: a
#: balance shaft for a few per cent of one cylinder's force is not worth fitting.
LEAVE_SHARE = 0.1


def _orders(values: list[int]) -> list[int]:
    bad = [v for v in values if v not in ALLOWED_ORDERS]
    if bad:
        raise ValueError(
            f"orders {bad} are not allowed: the exact piston acceleration has the first order and the "
            f"even orders only; allowed: {', '.join(map(str, ALLOWED_ORDERS))}"
        )
    if len(set(values)) != len(values):
        raise ValueError("each order once")
    return sorted(values)


def _include(values: list[int]) -> list[int]:
    values = _orders(values)
    if 1 not in values or 2 not in values:
        raise ValueError("must include the first and second orders (1, 2)")
    return values


def _top(value: int) -> int:
    if not 1 <= value <= 200:
        raise ValueError("must be a whole number from 1 to 200")
    return value


class BalancingOptions(RodOffsetOptions):
    """The [balancing] table (``rod_offset`` from the shared model: the distance along the crank
    pin between the planes of rods side by side on it; None, one big-end bearing's width:
    ``crankdyn.plugin.scene_inputs.rod_offset_m``)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    counterweight_radius: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    balance_shaft_radius: _quantity("length", gt=0, le=2.0, unit="mm", scale=1e-3) | None = None
    balance_shaft_spacing: _quantity("length", gt=0, le=20.0, unit="mm", scale=1e-3) | None = None
    include_orders: Annotated[list[int], AfterValidator(_include)] = [1, 2, 4, 6]
    # None: the first order (counterweights, and a shaft where the cranks leave a first-order
    # force or couple), the second too for a radial (:func:`balance_orders_for`)
    balance_orders: Annotated[list[int], AfterValidator(_orders)] | None = None
    counterweights: Literal["ends", "every_crank"] = "ends"
    first_order_forward: Literal["crankshaft", "shaft"] = "crankshaft"
    # "left": no balance shaft for the first order's counter-rotating part (a single's
    # counterweights alone, sized for C + C_I/2, leave C_I/2 turning against the shaft)
    first_order_backward: Literal["shaft", "left"] = "shaft"
    explore: bool = False
    explore_top: Annotated[int, AfterValidator(_top)] = 10


def balance_orders_for(scene, opts: BalancingOptions) -> list[int]:
    """The orders to balance: the scene's ``[balancing] balance_orders``, else [1, 2] for a
    radial (its second-order force turns at twice the shaft's speed, and a radial's balancer
    takes it with the first) and [1] for every other engine: counterweights, and a shaft where
    the cranks leave a first-order force or couple. Second-order shafts (two more, at twice the
    shaft's speed) are fitted only to some engines, so a scene asks for them; the section says
    what they would balance
    (:func:`crankdyn_builtin.balancing.section.second_order_left_by_default`)."""
    if opts.balance_orders is not None:
        return list(opts.balance_orders)
    radial = scene.engine.layout == "radial" and scene.engine.cylinders > 1
    return [1, 2] if radial else [1]


def flies_without_shafts(scene) -> bool:
    """An aircraft engine other than a radial: built without second-order balance shafts."""
    return scene.engine.application == "aircraft" and scene.engine.layout != "radial"
