"""Built-in analysis stages and their translation catalogs."""

from pathlib import Path

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Catalog

from .balancing import BALANCING_STAGE
from .bays import BAYS_STAGE
from .bearings import BEARINGS_STAGE
from .flywheel import FLYWHEEL_STAGE
from .forces import FORCES_STAGE
from .indicator import INDICATOR_STAGE
from .kinematics import KINEMATICS_STAGE
from .numerics import NUMERICS_KINEMATICS_STAGE, NUMERICS_STAGE
from .offset_crank import OFFSET_CRANK_STAGE
from .planetary import PLANETARY_STAGE
from .rod_dynamics import ROD_DYNAMICS_STAGE
from .speed_fluctuation import SPEED_FLUCTUATION_STAGE
from .torque import TORQUE_STAGE
from .vane import VANE_STAGE

CATALOG_DIR = Path(__file__).resolve().parent.parent / "i18n"


@hookimpl
def crankdyn_stages():
    return [KINEMATICS_STAGE, INDICATOR_STAGE, FORCES_STAGE, BAYS_STAGE, TORQUE_STAGE, BEARINGS_STAGE,
            NUMERICS_STAGE, NUMERICS_KINEMATICS_STAGE, BALANCING_STAGE,
            OFFSET_CRANK_STAGE, PLANETARY_STAGE, VANE_STAGE, ROD_DYNAMICS_STAGE,
            FLYWHEEL_STAGE, SPEED_FLUCTUATION_STAGE]


@hookimpl
def crankdyn_catalogs():
    # One file per topic and language, "<topic>.<language>.toml", so that stages added
    # independently never edit the same catalog file.
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted(CATALOG_DIR.glob("*.toml"))]
