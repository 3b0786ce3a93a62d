"""wetbounce from Python: particles (solid beads, liquid drops) in a fluid, bouncing on walls
with the rule of Legendre, Zenit, Daniel & Guiraud (2006).

    import wetbounce
    scene = wetbounce.Scene.load("scenes/toluene_drop.toml")
    scene.check()["kinds"]                 # what `wetbounce check` prints, as data
    sim = scene.simulation()
    sim.advance_to(0.5)                    # step, the GIL released
    sim.positions, sim.states              # NumPy arrays
    sim.events()                           # pandas DataFrame, the rows of events.csv
    scene.run("out/toluene_drop", formats=["mcap", "csv"])   # the CLI's files
    wetbounce.sweep(scene, {"kinds[0].restitution_max": [0.5, 0.9]})   # a Dask sweep

The classes are implemented in Rust (the extension module ``wetbounce._wetbounce``).
"""

from ._wetbounce import (
    STATE_NAMES,
    OutputError,
    Scene,
    SceneError,
    Simulation,
    __version__,
)
from .sweep import sweep

__all__ = ["STATE_NAMES", "OutputError", "Scene", "SceneError", "Simulation", "__version__", "sweep"]
