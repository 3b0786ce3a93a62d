"""Type stubs of wetbounce's extension module (python/src/*.rs); the docstrings are the Rust
doc comments, shown by ``help()``."""

from collections.abc import Mapping, Sequence
from os import PathLike
from pathlib import Path
from typing import Any, Final

import numpy as np
import numpy.typing as npt
import pandas as pd

__version__: Final[str]

STATE_NAMES: Final[tuple[str, str, str]]
"""The names of the state codes of :attr:`Simulation.states`: ``("free", "held", "resting")``."""

class SceneError(ValueError):
    """A scene that cannot be loaded; ``str(e)`` is the CLI's message ``FILE: KEY: what is
    wrong, with the value``."""

    file: str
    key: str
    message: str

class OutputError(OSError):
    """An output file that cannot be written; ``str(e)`` names each file and the OS error."""

    files: list[str]

class Scene:
    """A scene, loaded and validated as ``wetbounce run`` and ``wetbounce check`` load one."""

    @staticmethod
    def load(
        path: str | PathLike[str], *, allow_long_run: bool = False, allow_large_memory: bool = False
    ) -> Scene:
        """Reads and validates the scene file at ``path``."""

    @staticmethod
    def from_dict(
        scene: Mapping[str, Any],
        *,
        base_dir: str | PathLike[str] | None = None,
        allow_long_run: bool = False,
        allow_large_memory: bool = False,
    ) -> Scene:
        """Validates a scene given as a dict with a scene file's structure; messages name the
        file ``<dict>``."""

    def with_values(self, changes: Mapping[str, Any]) -> Scene:
        """A new scene with the keys (``"kinds[0].restitution_max"``) set, validated again;
        ``None`` removes a key."""

    def __getitem__(self, key: str) -> Any:
        """The value at a key path, as the scene gives it."""

    def to_dict(self) -> dict[str, Any]:
        """The scene as a dict (defaults not filled in)."""

    @property
    def source(self) -> str:
        """The scene as TOML text."""

    @property
    def path(self) -> Path:
        """The scene's file (``<dict>`` for a dict)."""

    @property
    def duration(self) -> float:
        """Simulated duration (s)."""

    @property
    def output_interval(self) -> float:
        """Simulated time between output frames (s)."""

    @property
    def dt(self) -> float:
        """The time step (s), the chosen one with ``dt = "auto"``."""

    def _repr_html_(self) -> str:
        """A summary table for Jupyter."""

    def check(self) -> dict[str, Any]:
        """What ``wetbounce check`` prints, as data; ``"kinds"`` is a list of dicts, one per
        kind and diameter."""

    def simulation(self) -> Simulation:
        """The simulation at time 0."""

    def run(
        self,
        out: str | PathLike[str] | None = None,
        *,
        formats: Sequence[str] | None = None,
        output_interval: float | None = None,
        max_spheres: int | None = None,
        name: str | None = None,
        quiet: bool = False,
    ) -> Simulation:
        """Runs a new simulation of the scene whole (see :meth:`Simulation.run`) and returns
        it."""

class Simulation:
    """A running simulation: step it, run it, read its particles, events and summary."""

    def advance_to(self, t: float) -> None:
        """Steps until the simulation's time is ``t`` (s), the GIL released."""

    def save(self, path: str | PathLike[str]) -> None:
        """Saves the whole state to ``path``, a checkpoint ``load`` and ``wetbounce resume`` go on from exactly."""

    @staticmethod
    def load(path: str | PathLike[str]) -> Simulation:
        """The simulation saved at ``path`` (by ``save`` or a run's checkpoint), at the time it was saved."""

    def run(
        self,
        out: str | PathLike[str] | None = None,
        *,
        formats: Sequence[str] | None = None,
        output_interval: float | None = None,
        max_spheres: int | None = None,
        name: str | None = None,
        quiet: bool = False,
        checkpoint_every: float | None = None,
        checkpoint_wall: float | None = None,
        checkpoint_keep: int = 2,
    ) -> Simulation:
        """Runs from time 0 to the scene's duration as ``wetbounce run`` does; with ``out``,
        writes its files there (``formats``: ``"mcap"``, ``"csv"``, ``"vtk"``, and ``"rrd"``
        in a build with rerun) and ``summary.json``, removing an earlier run's outputs it does
        not write. Returns the simulation, finished (the files written are :attr:`files`); a
        progress bar (tqdm's if installed) unless ``quiet``; raises :class:`OutputError` for
        any output failure, the folder's included."""

    @property
    def time(self) -> float:
        """Simulated time (s)."""

    @property
    def steps(self) -> int:
        """Steps taken."""

    @property
    def dt(self) -> float:
        """The time step (s)."""

    @property
    def duration(self) -> float:
        """The scene's duration (s)."""

    def __len__(self) -> int:
        """Number of particles in the simulation now."""

    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Centre positions (m), shape ``(n, 3)``."""

    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """Velocities (m/s), shape ``(n, 3)``."""

    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]:
        """Angular velocities (rad/s), shape ``(n, 3)``: ``trajectories.csv``'s ``wx, wy, wz``;
        all zero in a scene without rotation (no ``rotation`` effect, no friction key)."""

    @property
    def states(self) -> npt.NDArray[np.uint8]:
        """States, shape ``(n,)``: 0 free, 1 held, 2 resting (``STATE_NAMES``)."""

    @property
    def ids(self) -> npt.NDArray[np.uint32]:
        """Particle ids, shape ``(n,)``."""

    @property
    def diameters(self) -> npt.NDArray[np.float64]:
        """Diameters (m), shape ``(n,)``."""

    @property
    def kinds(self) -> npt.NDArray[np.uint16]:
        """Kind indices into :attr:`kind_names`, shape ``(n,)``."""

    @property
    def kind_names(self) -> list[str]:
        """The scene's particle kinds."""

    @property
    def wall_names(self) -> list[str]:
        """The scene's walls."""

    @property
    def left_field(self) -> dict[str, Any] | None:
        """The first particle found outside a flow field with ``outside = "error"``: ``id``,
        ``position`` (m), ``t`` (s), ``message``; ``None`` if none. ``run()`` stops there;
        ``advance_to`` goes on, so check this after it."""

    @property
    def files(self) -> list[Path]:
        """The files the last :meth:`run` wrote (``summary.json`` last)."""

    def record(self, times: Sequence[float]) -> pd.DataFrame:
        """Steps through ``times`` and returns the particles at each, ``t`` first: a long
        DataFrame, the rows of ``trajectories.csv`` at the output times."""

    def particles(self) -> pd.DataFrame:
        """The particles now: ``id``, ``kind`` (name), ``diameter``, ``x``, ``y``, ``z``,
        ``vx``, ``vy``, ``vz``, ``state`` and, with rotation, ``wx``, ``wy``, ``wz``."""

    def _repr_html_(self) -> str:
        """A summary table for Jupyter."""

    def events(self) -> pd.DataFrame:
        """Every contact so far: the columns and rows of ``events.csv``, with
        ``tangential_speed`` (m/s) and ``incidence_angle`` (rad) in a scene with rotation
        only (NaN for a removal)."""

    def residence_times(self) -> pd.DataFrame:
        """What each outlet took out: ``outlet``, ``id``, ``t``, ``residence_time``."""

    def summary(self) -> dict[str, Any]:
        """The summary so far, as the dict of ``summary.json``."""

    def summary_frames(self) -> dict[str, pd.DataFrame]:
        """The summary's ``"walls"``, ``"outlets"`` and ``"injectors"`` tables."""
