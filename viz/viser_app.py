"""viser app: the debugger's layers live in the browser.

Frame slider and play, method dropdown, BVH depth slider, a toggle per layer; click the mesh
to select the node at the chosen depth that holds the clicked triangle: its cone and contour
are drawn, and a panel gives its verdict and the reason in words, and its path to the root.
Binds 127.0.0.1 unless told otherwise; viser silently moves to the next free port, so the
real one is `app.port`.
"""

from __future__ import annotations

import contextlib
import io
import threading
import time
import traceback

import numpy as np
import trimesh
import viser

import conecull
from conecull.datasets import checks
from conecull.viz import layers as L
from conecull.viz.compare import timed_query
from conecull.viz.checks import check_host_port, check_method, url_host
from conecull.viz.explain import NO_CONES, explain_face, explain_node

HIGHLIGHT = (30, 90, 255)
DCD, CCD = "DCD: frame k", "CCD: step k → k + 1"  # the "query" dropdown
PARTNER = (20, 20, 20)  # the triangles the clicked one collides with (HIGHLIGHT: the clicked one)


def ray_triangle_hit(origin, direction, tri: np.ndarray):
    """Nearest triangle hit by a ray (Moller-Trumbore on all faces, vectorised), or None."""
    o, d = np.asarray(origin, float), np.asarray(direction, float)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-15
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = o - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    if not hit.any():
        return None
    idx = np.flatnonzero(hit)
    return int(idx[np.argmin(t[idx])])


def node_at_depth(bvh: dict, face: int, depth: int) -> int:
    """The node at `depth` (or the leaf, if shallower) whose triangle range holds `face`."""
    pos = int(np.flatnonzero(bvh["order"] == face)[0])
    node = 0
    while bvh["depth"][node] < depth and bvh["right"][node] >= 0:
        left = bvh["left"][node]
        node = left if bvh["begin"][left] <= pos < bvh["end"][left] else bvh["right"][node]
    return node


def box_segments(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(k * 12, 2, 3) edges of k boxes."""
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    edges = [(0, 1), (0, 2), (0, 4), (1, 3), (1, 5), (2, 3), (2, 6), (3, 7), (4, 5), (4, 6), (5, 7), (6, 7)]
    pts = lo[:, None, :] + corners[None] * (hi - lo)[:, None, :]
    return np.concatenate([pts[:, [a, b]] for a, b in edges], axis=0).reshape(-1, 2, 3)


def triangle_outlines(tri: np.ndarray, lift: float) -> np.ndarray:
    """(k * 6, 2, 3) edges of k triangles (k, 3, 3), drawn `lift` above and below each face (along
    its normal): on the face itself the mesh would hide them from one side or z-fight them."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    edges = np.stack([tri, tri[:, [1, 2, 0]]], axis=2)  # (k, 3 edges, 2 ends, 3)
    return np.concatenate([edges + s * lift * n[:, None, None] for s in (1.0, -1.0)]).reshape(-1, 2, 3)


def two_sided_mesh(V: np.ndarray, faces: np.ndarray, face_colors: np.ndarray) -> trimesh.Trimesh:
    """The mesh exploded (3 vertices per face, so each face keeps its own colour), each face twice,
    once per winding: the GLB carries no material, so the browser draws front faces only, and the
    underside of a folded flap would be missing (see-through)."""
    tri = V[faces]
    both = np.concatenate([tri, tri[:, ::-1]]).reshape(-1, 3)
    colors = np.repeat(np.concatenate([face_colors, face_colors]), 3, axis=0)
    return trimesh.Trimesh(vertices=both, faces=np.arange(len(both)).reshape(-1, 3), vertex_colors=colors,
                           process=False)


def legend_markdown(keys) -> str:
    """(name, rgb) pairs as one line of coloured squares."""
    return " · ".join(f"<span style='color:rgb{tuple(int(c) for c in rgb)}'>■</span> {name}" for name, rgb in keys)


def partners_of(pairs: np.ndarray, face: int) -> np.ndarray:
    """The triangles paired with `face` in (k, 2) pairs, sorted, without it."""
    mine = pairs[(pairs[:, 0] == face) | (pairs[:, 1] == face)]
    return np.setdiff1d(mine, [face])


def strip_segments(strips) -> np.ndarray:
    if not strips:
        return np.zeros((0, 2, 3))
    return np.concatenate([np.stack([s[:-1], s[1:]], axis=1) for s in strips])


class ViewerApp:
    def __init__(self, faces, frames, *, host: str = "127.0.0.1", port: int = 8080, method: str = "nc",
                 ccd: bool = False):
        """faces (m, 3), frames (T, n, 3); host and port to serve on (port 0: any free one); ccd:
        start with CCD steps (frame k shows the step from frame k to k + 1, as `record --ccd`)."""
        check_method(method)
        self.frames = checks.frames("frames", frames)
        if not isinstance(ccd, (bool, np.bool_)):
            raise ValueError(f"ccd: expected True or False, got {ccd!r}")
        if ccd and len(self.frames) < 2:
            raise ValueError(f"ccd: a CCD step needs two frames, the sequence has {len(self.frames)}")
        if ccd and method not in conecull.CCD_METHODS:
            raise ValueError(f"method: {method!r} is a discrete (DCD) method; CCD needs one of {conecull.CCD_METHODS}")
        mesh = conecull.Mesh(faces, n_vertices=self.frames.shape[1])
        if mesh.n_faces == 0:  # nothing to show, and no BVH to take depths from
            raise ValueError("faces: no triangles to view")
        self.faces = mesh.faces  # int64
        check_host_port(host, port)  # before the work below: viser hangs on what it cannot bind
        self.host = host
        self.colliders = {}
        for m in conecull.METHODS:
            col = conecull.SelfCollider(mesh, method=m)
            col.dcd(self.frames[0])  # node ids come from the first frame, as in `record`
            self.colliders[m] = col
        self.max_depth = int(self.colliders[method].bvh_arrays()["depth"].max())
        self.selected_face: int | None = None
        self.selection: dict = {}  # per-node drawings (selected node, clicked triangles): name -> handle
        # The frame each collider's last DCD / CCD query was at: its front of that kind came from there.
        # None: none yet (the fronts are kept per kind; only a DCD query of frame 0 has run).
        self.queried_at = {(m, kind): 0 if kind == DCD else None for m in self.colliders for kind in (DCD, CCD)}
        self._note = ""  # a refused control value, said in the stats panel with the next frame drawn
        self._lock = threading.Lock()
        self._stop = threading.Event()

        with contextlib.redirect_stdout(io.StringIO()):  # viser's own address banner: `view` prints the URL
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.port = self.server.get_port()
        # The scene's size, from the whole sequence: the camera's framing and the arrows' radii follow
        # it (fixed radii were hairlines on a mesh in millimetres, and the camera started inside it).
        lo, hi = self.frames.min(axis=(0, 1)), self.frames.max(axis=(0, 1))
        self.center, self.scale = 0.5 * (lo + hi), max(float(np.linalg.norm(hi - lo)), 1e-12)
        self.server.on_client_connect(self._frame_camera)
        gui = self.server.gui
        gui.add_markdown("**conecull** — why each region was culled or not")
        self.frame = gui.add_slider("frame", min=0, max=len(self.frames) - 1, step=1, initial_value=0)
        self.play = gui.add_checkbox("play", initial_value=False)
        # A CCD step needs two frames: a one-frame sequence offers DCD only.
        self.query = gui.add_dropdown("query", [DCD, CCD] if len(self.frames) > 1 else [DCD],
                                      initial_value=CCD if ccd else DCD)
        self.method = gui.add_dropdown("method", list(conecull.METHODS), initial_value=method)
        self.depth = gui.add_slider("BVH depth", min=0, max=self.max_depth, step=1, initial_value=min(4, self.max_depth))
        with gui.add_folder("layers"):
            self.show_mesh = gui.add_checkbox("mesh", initial_value=True)
            self.colour_by = gui.add_dropdown("mesh colour", ["verdict", "front load"], initial_value="verdict")
            self.show_contours = gui.add_checkbox("failing contours", initial_value=True)
            self.show_culled = gui.add_checkbox("culled patches' contours", initial_value=True)
            self.show_cones = gui.add_checkbox("cone axes", initial_value=False)
            self.show_failed = gui.add_checkbox("boxes of the nodes not culled", initial_value=False)
            self.show_boxes = gui.add_checkbox("BVH boxes at depth", initial_value=False)
        self.legend_md = gui.add_markdown(legend_markdown(L.status_legend()))  # follows the colouring shown
        self.stats_md = gui.add_markdown("")
        with gui.add_folder("methods at this frame"):
            self.compare = gui.add_checkbox("compare all methods", initial_value=False)
            self.compare_md = gui.add_markdown("")
        with gui.add_folder("selected node"):
            # A triangle by id too: a contact can lie between layers, out of a click's reach.
            self.pick = gui.add_number("select triangle", initial_value=-1, min=-1, max=len(self.faces) - 1, step=1)
            self.panel = gui.add_markdown("Click the mesh (or type a triangle id above) to select the node at the "
                                          "chosen depth that holds that triangle.")
        self.pick.on_update(lambda _event: self._pick())

        for handle in (self.frame, self.query, self.method, self.depth, self.show_mesh, self.colour_by, self.show_contours,
                       self.show_culled, self.show_cones, self.show_failed, self.show_boxes, self.compare):
            handle.on_update(lambda _event: self._update_or_show_error())
        # A click anywhere in the scene, then our own ray test on the shown pose: a click binding
        # on the mesh would make viser outline it when hovered, in yellow, on its back faces
        # (whole flaps of a folded sheet), which reads as "cone too wide".
        self.server.scene.on_click()(self._on_click)
        self.update()
        self._player = threading.Thread(target=self._play_loop, daemon=True)
        self._player.start()

    # --- state -----------------------------------------------------------------------------
    @property
    def col(self):
        return self.colliders[self.method.value]

    def _play_loop(self):
        while not self._stop.wait(0.3):
            if self.play.value:
                try:
                    self.frame.value = (int(self.frame.value) + 1) % (len(self.frames) - (1 if self.ccd else 0))
                except Exception:  # noqa: BLE001 - shown by _update_or_show_error; play goes on
                    pass

    def _update_or_show_error(self):
        """update() for the controls' callbacks: an error there (a bug) is printed and shown in the
        stats panel, and the controls and the player keep working (viser would only log it, and
        an error raised into the player's thread ended play for good)."""
        try:
            self.update()
        except Exception as e:  # noqa: BLE001
            traceback.print_exc()
            self.stats_md.content = f"**error while drawing this frame** ({type(e).__name__}: {e}); please report it"

    def _in_range(self, handle, hi: int, what: str, why: str = "") -> int | None:
        """handle's value if in 0..hi; else None, after noting the refusal and setting the handle to
        the nearest valid value (which draws that): a slider's number box sends each keystroke
        unclamped (99, -1), and -1 would index from the end."""
        v = handle.value
        if float(v).is_integer() and 0 <= v <= hi:
            return int(v)
        near = int(min(max(round(float(v)), 0), hi)) if np.isfinite(float(v)) else 0
        self._note += f"**{what} {v} refused**: {what}s are 0..{hi}{why}; showing {near}. "
        handle.value = near  # differs from v: viser calls the handle's callbacks, which draw it
        return None

    @property
    def ccd(self) -> bool:
        return self.query.value == CCD

    def update(self):
        ccd = self.ccd  # once, as the method below
        last = len(self.frames) - (2 if ccd else 1)  # CCD: the last frame starts no step
        k = self._in_range(self.frame, last, "step" if ccd else "frame",
                           f" (step k goes from frame k to k + 1; the last frame, {last + 1}, starts none)" if ccd else "")
        d = self._in_range(self.depth, self.max_depth, "BVH depth")
        if k is None or d is None:
            return  # set back into range, which drew the frame
        if ccd and self.method.value not in conecull.CCD_METHODS:
            self._note += f"**{self.method.value} is a discrete (DCD) method**: showing nc for CCD. "
            self.method.value = "nc"  # its callback draws it
            return
        with self._lock:
            self.k, self.d = k, d
            m = self.method.value  # once: the dropdown may change while this frame is drawn
            col = self.colliders[m]
            kind = CCD if ccd else DCD
            since = self.queried_at[m, kind]
            # CCD: the step from frame k to k + 1, drawn (and clicked) at its end pose, as `record --ccd`.
            V = self.frames[k + 1] if ccd else self.frames[k]
            res = col.ccd(self.frames[k], V, trace=True, toi=True) if ccd else col.dcd(V, trace=True)
            self.queried_at[m, kind] = k
            self.res, self.V = res, V
            self.colliding = L.colliding_triangles(col, res)  # for the stats line and every click
            lay = L.compute(col, self.faces, V, res)
            scene = self.server.scene
            with self.server.atomic():
                # "front load": how many BVTT front entries reach each face (front methods, Alg. 4)
                by_front = self.colour_by.value == "front load" and m.endswith("+front")
                load = col.front_load("ccd" if ccd else "dcd") if by_front else None
                face_colors = L.front_colors(load) if by_front else lay.face_colors
                self.face_colors = face_colors
                self.legend_md.content = legend_markdown(L.front_legend(load) if by_front else L.status_legend())
                scene.add_mesh_trimesh("/mesh", two_sided_mesh(V, self.faces, face_colors),
                                       visible=bool(self.show_mesh.value))
                segs = strip_segments(lay.contour_strips)
                colors = np.repeat(np.array([L.REASON_COLORS[int(c)] for c in lay.contour_reasons], np.uint8).reshape(-1, 3),
                                   [len(s) - 1 for s in lay.contour_strips], axis=0) if len(segs) else np.zeros((0, 3), np.uint8)
                scene.add_line_segments("/contours", segs.reshape(-1, 2, 3), np.repeat(colors[:, None], 2, axis=1),
                                        thickness=2.0, thickness_units="screen", visible=bool(self.show_contours.value))
                segs = strip_segments(lay.culled_strips)
                scene.add_line_segments("/culled", segs.reshape(-1, 2, 3), L.CULLED_CONTOUR_COLOR, thickness=1.0,
                                        thickness_units="screen", visible=bool(self.show_culled.value))
                # the bounded cones' axes, culled nodes' included (a cone too wide has no axis)
                arrows = np.stack([lay.axis_origins, lay.axis_origins + lay.axis_vectors], axis=1)
                scene.add_arrows("/cones", arrows.reshape(-1, 2, 3), lay.axis_colors,
                                 shaft_radius=0.0015 * self.scale, head_radius=0.0045 * self.scale,
                                 head_length=0.009 * self.scale, visible=bool(self.show_cones.value))
                # box_segments lists edge by edge over all boxes: the colours repeat per edge
                scene.add_line_segments("/failed_nodes", box_segments(lay.box_lo, lay.box_hi),
                                        np.repeat(np.tile(lay.node_colors, (12, 1))[:, None], 2, axis=1), thickness=1.5,
                                        thickness_units="screen", visible=bool(self.show_failed.value))
                bvh = col.bvh_arrays()
                sel = np.flatnonzero(bvh["depth"] == d)
                scene.add_line_segments("/bvh", box_segments(bvh["box"][sel, 0], bvh["box"][sel, 1]), (120, 120, 200),
                                        thickness=1.0, thickness_units="screen", visible=bool(self.show_boxes.value))
                note, self._note = self._note, ""
                self.stats_md.content = note + self._stats_line(k, res.stats, since)
                self._draw_selection()
            self.compare_md.content = self._compare_table(k, ccd) if self.compare.value else ""

    def _frame_camera(self, client) -> None:
        """A new browser tab looks at the whole sequence's box from outside it, whatever its units."""
        client.camera.look_at = tuple(float(x) for x in self.center)
        client.camera.position = tuple(float(x) for x in self.center + self.scale * np.array([0.8, -0.8, 0.6]))

    def _stats_line(self, k: int, s: dict, since: int) -> str:
        front = s["method"].endswith("+front")
        ccd = "vf_contacts" in s
        where = f"step **{k} → {k + 1}** (drawn at frame {k + 1})" if ccd else f"frame **{k}**"
        found = (f"vertex-face tests {s['vf_tests']} · edge-edge tests {s['ee_tests']} · contacts "
                 f"**{s['vf_contacts']} vertex-face, {s['ee_contacts']} edge-edge**" if ccd else
                 f"elementary tests {s['elementary_tests']} · colliding pairs **{s['colliding_pairs']}**")
        # A front method resumes the front its previous query left (Alg. 4): its counters are
        # relative to the frame that query was at, not only to this frame.
        return (f"{where} · method **{s['method']}** · cone tests {s['cone_tests']} · culled "
                f"{s['contour_passed']} · contour failed {s['contour_failed']} · {found}"
                + (f" · front entries {s['front_entries']} (+{s['front_added']} / -{s['front_removed']} "
                   f"{self._since(since, k, ccd)}; {s['front_rested']} nodes resting)" if front else "")
                + (" · *front load needs a +front method*" if self.colour_by.value == "front load"
                   and not front else "")
                + self._colliders_line())

    @staticmethod
    def _since(since: int | None, k: int, ccd: bool) -> str:
        """Whence a front method's front came: that collider's previous query of this kind."""
        what = "step" if ccd else "frame"
        if since is None:
            return f"since no earlier {'CCD' if ccd else 'DCD'} query: built from the top"
        kept = f"the front is kept between queries, so this depends on the {what} shown before"
        return f"since {what} {since}, {kept}" if since != k else f"since {what} {k} itself (a re-query of this pose)"

    def _colliders_line(self, shown: int = 12) -> str:
        """The colliding triangles of the shown query, the first `shown` named: a click target
        (a contact can hide between layers), or type one into "select triangle"."""
        faces = np.unique(self.colliding)
        if len(faces) == 0:
            return ""
        more = f", … ({len(faces)} in all)" if len(faces) > shown else ""
        return (f"\n\ncolliding triangles: {', '.join(str(int(f)) for f in faces[:shown])}{more} "
                "(type one into *select triangle*)")

    def _compare_table(self, k: int, ccd: bool) -> str:
        """Every method's untraced query at this pose (CCD: this step, the methods for CCD):
        contour-test time (the contour tests of Fig. 9, per method) and the counters. Each method
        has its own collider (its own front); the front methods' rows resume the front of that
        collider's previous query, for the shown method a query of this very pose: the last
        column says which."""
        tests = "vertex-face + edge-edge tests" if ccd else "elementary tests"
        rows = [f"| method | contour tests | culled | contour ms | {tests} | query ms | front from |",
                "|---|---|---|---|---|---|---|"]
        kind = CCD if ccd else DCD
        for m, col in self.colliders.items():
            if ccd and m not in conecull.CCD_METHODS:
                continue
            since = self.queried_at[m, kind]
            res, ms = timed_query(col, self.frames[k], self.frames[k + 1]) if ccd else timed_query(col, self.frames[k])
            self.queried_at[m, kind] = k
            s = res.stats
            what = "step" if ccd else "frame"
            front = ("—" if not m.endswith("+front") else "none: built from the top" if since is None else
                     f"{what} {since}" if since != k else f"{what} {k}: re-query of this pose")
            rows.append(f"| {m} | {s['contour_tests']} | {s['contour_passed']} | {1e3 * s['seconds_contour']:.3f} | "
                        f"{s['elementary_tests']} | {ms:.1f} | {front} |")
        return "\n".join(rows)

    def _on_click(self, event):
        """A click in the scene (SceneClickEvent): select the shown mesh's triangle under it, if any."""
        face = ray_triangle_hit(event.ray_origin, event.ray_direction, self.V[self.faces])
        if face is None:
            return
        with self._lock:
            self.selected_face = face
            with self.server.atomic():
                self._draw_selection()

    def _pick(self):
        """The "select triangle" box: an id in range selects it (as a click would); anything else
        is said in the panel."""
        v = self.pick.value
        if v == -1:
            return
        if not (float(v).is_integer() and 0 <= v < len(self.faces)):
            self.panel.content = f"**triangle {v} refused**: triangles are 0..{len(self.faces) - 1}"
            return
        self.select_face(int(v))

    def select_face(self, face: int):
        """Programmatic click (tests, scripts)."""
        face = checks.count("face", face, 0, len(self.faces) - 1)
        with self._lock:
            self.selected_face = face
            self._draw_selection()

    def _clear_selection(self):
        """Remove every per-node drawing: each query (frame, method, depth) or click draws its own."""
        for handle in self.selection.values():
            handle.remove()
        self.selection = {}

    def _draw(self, kind: str, name: str, *args, **kwargs):
        self.selection[name] = getattr(self.server.scene, kind)(name, *args, **kwargs)

    def _draw_selection(self):
        self._clear_selection()
        if self.selected_face is None:
            return
        # The collider that answered the shown query: the method dropdown may already be ahead of it.
        col = self.res.collider() or self.col
        bvh = col.bvh_arrays()
        node = node_at_depth(bvh, self.selected_face, self.d)
        text = explain_node(col, self.res, node)
        partners = partners_of(self.colliding, self.selected_face)
        self._draw_triangles(partners)
        if len(partners):
            # A colliding triangle: with which, and why no node holding both was culled (the
            # node at the chosen depth alone may be culled: the pair lies across two of them).
            text = (f"collides with triangles {', '.join(str(int(f)) for f in partners)}\n"
                    + explain_face(col, self.res, self.selected_face, limit=3)
                    + f"\nThe node at the chosen depth, {node}, holds this triangle; its verdict (below) is about "
                      "collisions among its own triangles only.\n" + text)
        marked = (f" · outlined on the mesh: it in blue, the {len(partners)} it collides with in black"
                  if len(partners) else " · outlined in blue on the mesh")
        when = f"step {self.k} → {self.k + 1}" if hasattr(self.res, "vf") else f"frame {self.k}"
        self.panel.content = f"triangle {self.selected_face} → node **{node}** ({when}){marked}\n\n" + \
            "\n\n".join(text.splitlines())
        ct = col.contour_arrays()
        loop = ct["vertices"][ct["offsets"][node] : ct["offsets"][node + 1]]
        if len(loop) and col.method not in NO_CONES:  # a contour matters only with cones
            pts = self.V[np.append(loop, loop[0])]
            self._draw("add_line_segments", "/selected/contour", np.stack([pts[:-1], pts[1:]], axis=1), HIGHLIGHT,
                       thickness=4.0, thickness_units="screen")
        cones = col.cone_arrays()
        if len(cones["axis"]) > node and np.any(cones["axis"][node]):  # a cone too wide has no axis (zero)
            c = 0.5 * (bvh["box"][node, 0] + bvh["box"][node, 1])
            size = float(np.linalg.norm(bvh["box"][node, 1] - bvh["box"][node, 0]))
            self._draw("add_arrows", "/selected/cone", np.array([[c, c + cones["axis"][node] * 0.6 * size]]),
                       HIGHLIGHT, shaft_radius=0.003 * self.scale, head_radius=0.009 * self.scale,
                       head_length=0.015 * self.scale)

    def _draw_triangles(self, partners: np.ndarray):
        """Outline the clicked triangle (HIGHLIGHT) and those it collides with (PARTNER)."""
        lift = 1e-3 * float(np.linalg.norm(np.ptp(self.V, axis=0)))
        for name, faces, color in (("/selected/triangle", [self.selected_face], HIGHLIGHT),
                                   ("/selected/partners", partners, PARTNER)):
            if len(faces):
                self._draw("add_line_segments", name, triangle_outlines(self.V[self.faces[faces]], lift), color,
                           thickness=3.0, thickness_units="screen")

    def close(self):
        self._stop.set()
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "Server stopped"
            self.server.stop()


def serve_forever(app: ViewerApp) -> None:  # pragma: no cover - interactive
    where = f", listening on all interfaces ({app.host})" if app.host in ("0.0.0.0", "::") else ""
    print(f"conecull view: open http://{url_host(app.host)}:{app.port} (Ctrl+C to stop{where})", flush=True)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass
    finally:
        app.close()
