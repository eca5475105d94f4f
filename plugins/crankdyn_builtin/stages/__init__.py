"""Built-in analysis stages and their translation catalogs."""

from pathlib import Path

from crankdyn.hookspecs import hookimpl
from crankdyn.plugin_types import Catalog

from .bays import BAYS_STAGE
from .bearings import BEARINGS_STAGE
from .forces import FORCES_STAGE
from .indicator import INDICATOR_STAGE
from .kinematics import KINEMATICS_STAGE
from .torque import TORQUE_STAGE

CATALOG_DIR = Path(__file__).resolve().parent.parent / "i18n"


@hookimpl
def crankdyn_stages():
    return [KINEMATICS_STAGE, INDICATOR_STAGE, FORCES_STAGE, BAYS_STAGE, TORQUE_STAGE, BEARINGS_STAGE]


@hookimpl
def crankdyn_catalogs():
    # One file per topic and language, "<topic>.<language>.toml", so that stages added
    # independently never edit the same catalog file.
    return [Catalog(language=p.stem.rsplit(".", 1)[-1], path=p) for p in sorted(CATALOG_DIR.glob("*.toml"))]
