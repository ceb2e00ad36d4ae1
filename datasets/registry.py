"""Scene registry: each scene is a small declaration (mesh generator with a resolution, the
effects it needs, initial conditions, frame count and time step) and `load` caches what it
generates on disk by its parameters.

Kinematic scenes (no effects) are analytic motions. Simulated scenes (effects such as gravity,
stretch/bend constraints, colliders, self-contact) arrive with the simulator; `effects` lists
what each declares, and only those are ever computed.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import json
import os
import re
import tempfile
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from conecull.datasets import cloth, generated, skirt, squishy
from conecull.datasets.checks import count, first_out_of_range, fits_in_memory

CACHE_VERSION = 1
# load's frame count: a simulated scene takes milliseconds to a second per frame, so a count
# beyond this is a typo that would run for hours, not a sequence anyone waits for.
MAX_FRAMES = 10_000


@dataclass(frozen=True)
class Scene:
    name: str
    description: str
    stands_for: str                      # which paper benchmark (Sec. 5.2) it stands in for, or "teaching"
    generate: Callable                   # (resolution, frames, dt) -> (faces (m, 3), positions (T, n, 3))
    triangles: Callable                  # resolution -> number of triangles
    default_resolution: int
    default_frames: int
    effects: tuple = field(default=())   # () = kinematic
    dt: float = 1.0 / 30.0               # seconds between frames (simulated scenes step with it)


def _grid_triangles(resolution: int) -> int:
    return 2 * (resolution - 1) ** 2


def _roll(resolution: int, frames: int, dt: float):
    """A strip curling around a small cylinder until its end comes back onto the strip."""
    F, V = generated.grid_sheet(resolution, max(2, resolution // 8), width=1.0, height=0.12)
    angles = np.linspace(0.0, 2.25 * np.pi, frames)
    return F, np.stack([generated.fold(V, a, x0=0.45, radius=0.07) for a in angles])


def _fold(resolution: int, frames: int, dt: float):
    return generated.folding_sheet(n_triangles=_grid_triangles(resolution), n_frames=frames)


def _crumple(resolution: int, frames: int, dt: float):
    return generated.crumpling_sphere(n_lat=resolution, n_lon=2 * resolution, n_frames=frames)


def _bend(resolution: int, frames: int, dt: float):
    return generated.bending_sheet(n_triangles=_grid_triangles(resolution), n_frames=frames)


def _simulated_scene(name, description, stands_for, setup, triangles, resolution, frames, effects) -> Scene:
    """A simulated scene: its set-up's effects must be exactly the declared ones (the simulator
    refuses the set-up otherwise), so an effect a scene does not declare never runs."""
    from conecull.datasets.sim import Simulator

    def generate(res: int, n_frames: int, dt: float):
        F, V, built, options = setup(res)
        return F, Simulator(F, V, built, dt=dt, declared=effects, **options).run(n_frames)

    return Scene(name, description, stands_for, generate, triangles, resolution, frames, effects)


def _flamenco(resolution: int, frames: int, dt: float):
    return skirt.skirt_sequence(resolution, frames)


def _squishy(resolution: int, frames: int, dt: float):
    return squishy.squishy_sequence(resolution, frames)


CLOTH = ("gravity", "stretch", "bend")
SCENES: dict[str, Scene] = {
    s.name: s
    for s in (
        Scene("fold", "a sheet folding onto itself until it passes through", "teaching", _fold, _grid_triangles, 33, 30),
        Scene("roll", "a strip curling into a spiral until it touches itself", "teaching", _roll,
              lambda r: 2 * (r - 1) * (max(2, r // 8) - 1), 64, 30),
        Scene("crumple", "a sphere crumpling inwards until it self-intersects", "teaching", _crumple,
              lambda r: 2 * r * 2 * r - 4 * r, 22, 30),
        Scene("bend", "a gently bending sheet (never self-intersects)", "teaching", _bend, _grid_triangles, 33, 30),
        _simulated_scene("funnel", "a sheet falling into a funnel, folding to fit, with self-contact", "Funnel",
                         cloth.funnel, _grid_triangles, 180, 60, CLOTH + ("funnel", "self-contact")),
        _simulated_scene("twisting", "a sheet dropped on a ball spinning about the vertical, with self-contact",
                         "Twisting", cloth.twisting, _grid_triangles, 180, 60,
                         CLOTH + ("sphere", "plane", "self-contact")),
        _simulated_scene("flowing", "a sheet pinned at two corners in gusty wind, with self-contact", "FlowingCloth",
                         cloth.flowing, _grid_triangles, 159, 60,
                         CLOTH + ("wind", "pinned", "tethers", "self-contact")),
        _simulated_scene("falling", "a robe thrown down fast over a body proxy, with self-contact", "Falling",
                         cloth.falling, lambda r: len(cloth.robe_sheet(r)[0]), 295, 45,
                         CLOTH + ("strain-limit", "capsule", "sphere", "plane", "self-contact")),
        Scene("flamenco", "a keyframed skirt with ruffles that lean over and press together", "Flamenco",
              _flamenco, lambda r: 10 * r * r, 70, 60),
        Scene("squishy", "a ball with 96 tentacles dropped and squashed on the ground", "SquishyBall",
              _squishy, lambda r: squishy.squishy_counts(r)[0], 160, 20),
    )
}


def names() -> list[str]:
    return list(SCENES)


def cache_dir() -> Path:
    """$CONECULL_CACHE, else the user's cache directory (XDG_CACHE_HOME or ~/.cache)/conecull."""
    env = os.environ.get("CONECULL_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "conecull"


def _module_file(root: Path, module: str) -> Path | None:
    """The source of a module of this package (`conecull.datasets...`), None for any other."""
    if module != "conecull.datasets" and not module.startswith("conecull.datasets."):
        return None
    base = root.joinpath(*module.split(".")[2:])
    for f in (base / "__init__.py", base.with_suffix(".py")):
        if f.is_file():
            return f
    return None  # a name imported from a module, not a module


def generation_sources() -> list[Path]:
    """The package's source files a generated sequence can depend on: this module (the scenes'
    declarations) and every module of the package it imports, directly or not, read from their
    import statements (so a new import is followed). The loaders of real data (mesh files, input
    resolution, the shared steps) are not among them: editing those keeps the cache."""
    root = Path(__file__).parent
    todo, found = ["conecull.datasets.registry"], set()
    while todo:
        module = todo.pop()
        f = _module_file(root, module)
        if f is None or f in found:
            continue
        found.add(f)
        parts = (module if f.name == "__init__.py" else module.rpartition(".")[0]).split(".")  # its package
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"), str(f))):
            if isinstance(node, ast.Import):
                todo += [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = ".".join(parts[:len(parts) - node.level + 1]) if node.level else ""
                target = ".".join(x for x in (base, node.module or "") if x)
                todo.append(target)
                todo += [f"{target}.{a.name}" for a in node.names]  # `from package import module`
    return sorted(found)


def _code_digest() -> str:
    """The source of what generates the scenes (generation_sources: generators, scenes,
    simulator): editing any of it invalidates cached sequences."""
    h = hashlib.sha256()
    root = Path(__file__).parent
    for f in generation_sources():
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def _core_digest() -> str:
    """The built C++ core: the simulator's self-contact runs its exact CCD every substep, so a
    change there can change a simulated sequence (any rebuild counts: the binary is hashed)."""
    from conecull import _core

    return hashlib.sha256(Path(_core.__file__).read_bytes()).hexdigest()[:16]


def _key(scene: Scene, resolution: int, frames: int) -> str:
    blob = json.dumps({"v": CACHE_VERSION, "code": _code_digest(), "scene": scene.name, "res": resolution,
                       "frames": frames, "effects": list(scene.effects), "dt": scene.dt,
                       "core": _core_digest() if scene.effects else None}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def load(name: str, resolution: int | None = None, frames: int | None = None):
    """faces (m, 3) int64 and positions (T, n, 3) float64 of a scene; cached on disk.
    Positions are always finite: a scene that generates NaN or inf raises (and caches nothing)."""
    if not isinstance(name, str) or name not in SCENES:
        raise ValueError(f"name: unknown scene {name!r}; known: {', '.join(SCENES)}")
    scene = SCENES[name]
    resolution = count("resolution", scene.default_resolution if resolution is None else resolution, 3)
    frames_given = frames is not None  # a size error names what the caller chose (the CLI sets no frame count)
    frames = count("frames", scene.default_frames if frames is None else frames, 1, MAX_FRAMES)
    folder = cache_dir()
    if folder.exists() and not folder.is_dir():  # before generating, not after: mkdir would fail there
        source = "CONECULL_CACHE" if os.environ.get("CONECULL_CACHE") else "the cache folder"
        raise ValueError(f"{source}: '{folder}' is not a folder")
    path = folder / f"{name}-{_key(scene, resolution, frames)}.npz"
    if path.exists():
        return _read_cached(path, frames, scene.triangles(resolution))
    _check_writable(folder)
    try:
        n_triangles = scene.triangles(resolution)
    except ValueError as e:
        raise ValueError(f"resolution: {resolution} does not suit scene '{name}' ({e})") from None
    # Before generating (a frame count like 10^12 would run for ever): the positions alone take
    # frames x vertices x 24 bytes, with vertices at least about half the triangles.
    frame_bytes = 24.0 * (n_triangles / 2 + 1)
    fits_in_memory("resolution", frame_bytes, f"one frame of scene '{name}' at resolution {resolution}")
    fits_in_memory("frames" if frames_given else "resolution", frames * frame_bytes,
                   f"{frames} frames of scene '{name}' at resolution {resolution}")
    try:
        F, P = scene.generate(resolution, frames, scene.dt)
    except MemoryError:
        raise MemoryError(f"resolution, frames: scene '{name}' at resolution {resolution} with {frames} frames needs "
                          "more memory than this machine has") from None
    except ValueError as e:  # a generator's own limits (e.g. squishy's cells per side) are on the resolution
        raise ValueError(f"resolution: {resolution} does not suit scene '{name}' ({e})") from None
    F, P = np.asarray(F, np.int64), np.asarray(P, np.float64)
    bad = ~np.isfinite(P)
    if bad.any():  # a bug in the scene: never hand out (or cache) positions no query accepts
        k, i = (int(x) for x in np.argwhere(bad)[0][:2])
        raise ValueError(f"scene '{name}' at resolution {resolution}: generated a non-finite position (frame {k}, "
                         f"vertex {i}, {int(bad.any(axis=2).sum())} vertex positions in all); nothing was cached")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, faces=F, positions=P, meta=np.array(_meta(name, resolution, frames)))
    os.replace(tmp, path)  # atomic: a concurrent reader never sees half a file
    _prune_stale(folder, name, resolution, frames, keep=path)
    return F, P


def _meta(name: str, resolution: int, frames: int) -> str:
    """What a cache file holds, stored in it (array 'meta'): which files _prune_stale may delete."""
    return json.dumps({"scene": name, "res": resolution, "frames": frames}, sort_keys=True)


def _prune_stale(folder: Path, name: str, resolution: int, frames: int, keep: Path) -> None:
    """Deletes the other cache files of the same scene, resolution and frame count: written before
    the generators or (for a simulated scene) the core changed, they are read again only if that
    version comes back, and each takes up to a GB (squishy at 80 frames: 1.1 GB). Without this the
    folder grew by every scene at every rebuild of the core. Files of other resolutions or frame
    counts are kept, and so is any file this cannot read or that holds no 'meta' (written before
    it was stored: delete those by hand, or the folder)."""
    pattern = re.compile(re.escape(name) + r"-[0-9a-f]{16}\.npz")
    for f in folder.iterdir():
        if f == keep or not pattern.fullmatch(f.name):
            continue
        try:
            with np.load(f, allow_pickle=False) as z:
                meta = str(z["meta"]) if "meta" in z.files else None
        except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error):
            continue
        if meta == _meta(name, resolution, frames):
            try:
                f.unlink()
            except OSError:  # gone already (another process pruned it), or not ours to delete
                pass


def _check_writable(folder: Path) -> None:
    """Before generating (minutes for the large scenes): the folder the result will be cached in
    can be created and written, else an error naming where the folder came from."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".write-check-"):
            pass
    except OSError as e:
        source = ("CONECULL_CACHE" if os.environ.get("CONECULL_CACHE")
                  else "the cache folder (set CONECULL_CACHE to a writable folder to use another)")
        raise ValueError(f"{source}: cannot write scenes to '{folder}' ({e.strerror or e})") from None


def _read_cached(path: Path, frames: int, n_triangles: int):
    """A cached scene, checked as a generated one is before it is written (shapes, the scene's
    triangle count, ids, distinct corners, positions a query takes): a damaged or foreign file is
    an error naming it, never a sequence handed out."""
    def damaged(why: str):
        return ValueError(f"cache: '{path}' is damaged or not a scene cache ({why}); delete it, and the next "
                          "load generates the scene again")

    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in ("faces", "positions") if k in z.files}
    # Truncated, empty, not an npz, pickled, a broken deflate stream, a header shape beyond int64:
    except (OSError, ValueError, EOFError, OverflowError, zipfile.BadZipFile, zlib.error) as e:
        raise damaged(str(e) or type(e).__name__) from None
    except MemoryError:  # a damaged header claiming a huge array
        raise damaged("an array larger than this machine's memory") from None
    for k in ("faces", "positions"):
        if k not in arrays:
            raise damaged(f"no array '{k}'")
    F, P = arrays["faces"], arrays["positions"]
    if F.dtype != np.int64 or F.ndim != 2 or F.shape[1:] != (3,):
        raise damaged(f"faces {F.dtype} {F.shape}, expected int64 (m, 3)")
    if P.dtype != np.float64 or P.ndim != 3 or P.shape[0] != frames or P.shape[2] != 3:
        raise damaged(f"positions {P.dtype} {P.shape}, expected float64 ({frames}, n, 3)")
    if len(F) != n_triangles:
        raise damaged(f"{len(F)} triangles, the scene has {n_triangles}")
    if F.size and (F.min() < 0 or F.max() >= P.shape[1]):
        raise damaged(f"face ids outside [0, {P.shape[1]})")
    if (F[:, [0, 1, 2]] == F[:, [1, 2, 0]]).any():
        raise damaged("a triangle repeats a vertex")
    if not np.isfinite(P).all():
        raise damaged("a non-finite position")
    if (why := first_out_of_range(P)) is not None:
        raise damaged(why)
    return F, P


def min_resolution(scene: Scene) -> int:
    """The smallest resolution `load` takes for the scene (3, or more where the mesh needs it)."""
    for r in range(3, scene.default_resolution + 1):
        try:
            scene.triangles(r)
            return r
        except (ValueError, ZeroDivisionError):
            continue
    return scene.default_resolution


def describe() -> list[str]:
    """One line per scene: name, triangles at the default resolution, frames, the resolution
    (default and least; `--resolution` sets it), stands for, effects, description."""
    rows = [(s.name, str(s.triangles(s.default_resolution)), str(s.default_frames),
             f"{s.default_resolution} (>= {min_resolution(s)})", s.stands_for,
             ", ".join(s.effects) if s.effects else "kinematic", s.description) for s in SCENES.values()]
    # column widths from the contents, so a long effects list never shifts the columns after it
    w = [max(len(r[c]) for r in rows) for c in range(6)]
    return [f"{n:{w[0]}s}  {t:>{w[1]}s} triangles  {f:>{w[2]}s} frames  resolution {r:{w[3]}s}  {p:{w[4]}s}  "
            f"{e:{w[5]}s}  {d}" for n, t, f, r, p, e, d in rows]
