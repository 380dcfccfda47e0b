"""Kinematic analysis of geared mechanisms by the method of seed 000 (Penaud, Alazard, Amiez 2012).

Steps (seed 000 §2):

1. adjacency table ``T`` with complex gear weights ``N·e^{iθ}`` (§2.2);
2. reference link (carrier) of each gear pair, ``k = S_i ∩ S_j`` (eq 1);
3. constraint matrix ``M`` (first row fixes the frame, then one Willis row per gear pair, eq 2);
4. ``N_dof = N − rank(M)`` (eq 4) and the velocity-ratio matrix ``Ω0 = ker(M)`` normalised to
   chosen input links, ``Ω = Ω0 Λ`` (eq 5).

Angular velocities are complex numbers ``|ω|e^{iφ}``: ``φ`` is the direction of the rotation
vector in the plane of the kinematic sketch, positive clockwise (seed 000 §2.5).

Axes and input speeds. Each multiple turning pair is one physical axis with a direction ``φ``
(mod π) in the sketch plane. A gear pair (a, b) with carrier k turns a and b relative to k
about their axes, so Willis (eq 2) holds with real relative speeds only if
``θ_a + φ_a ≡ θ_b + φ_b (mod π)`` (both contact velocities along the common tooth axis): the
pitch angles fix every axis direction relative to the axis of the first link (in the order of
``links``) turning in the frame, which is the sketch direction 0° (:func:`axis_directions`;
directions folded into (−90°, 90°]).
The physical motions are the real relative rotations about these axes that satisfy every
Willis row (:attr:`KinematicAnalysis.physical`): they do not depend on the input links. An
input speed is the signed speed of its link about the link's own axis,
``s = Re(e^{−iφ} ω)`` (positive: rotation vector along ``e^{iφ}``; for a link on a moving
carrier, the component of its absolute rotation along its own axis); any set of ``dof``
inputs whose speeds fix the physical motion is accepted (:meth:`velocity_ratios`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from geardyn.errors import InputError, KinematicsError
from geardyn.kinematics.graph import GearMesh, MechanismGraph

if TYPE_CHECKING:  # imported where used (~0.6 s): config loading calls this module
    import pandas as pd

#: Relative singular-value threshold used for rank decisions on the row-normalised M.
RANK_RTOL = 1e-9


def multi_turning_pairs(graph: MechanismGraph) -> list[tuple[str, frozenset[str]]]:
    """Multiple turning pairs: connected groups of turning pairs on the same axis level.

    Returns ``(level, links)`` tuples (seed 000 §2.1: turning pairs on one level form a multiple
    turning pair, drawn as a shaded polygon in the graph).
    """
    groups: list[tuple[str, frozenset[str]]] = []
    by_level: dict[str, list[tuple[str, str]]] = {}
    for j in graph.joints:
        by_level.setdefault(j.axis, []).append((j.link_a, j.link_b))
    for level, edges in by_level.items():
        names = sorted({x for e in edges for x in e})
        pos = {x: i for i, x in enumerate(names)}
        rows = [pos[a] for a, _ in edges]
        cols = [pos[b] for _, b in edges]
        adj = coo_matrix((np.ones(len(edges)), (rows, cols)), shape=(len(names), len(names)))
        _, label = connected_components(adj, directed=False)
        for c in range(label.max() + 1):
            groups.append(
                (level, frozenset(n for n, lab in zip(names, label, strict=True) if lab == c))
            )
    return groups


def turning_neighbourhood(graph: MechanismGraph) -> dict[str, set[str]]:
    """``S_i`` of seed 000 §2.3 for every link: links joined to it by a (multiple) turning pair."""
    s: dict[str, set[str]] = {name: set() for name in graph.links}
    for _level, comp in multi_turning_pairs(graph):
        for link in comp:
            s.setdefault(link, set()).update(comp - {link})
    return s


def reference_link(mesh: GearMesh, s: Mapping[str, set[str]]) -> str:
    """Carrier of a gear pair, ``k = S_i ∩ S_j`` (seed 000 eq 1).

    Raises :class:`KinematicsError` naming the gear pair when the intersection is empty (no
    common carrier) or holds more than one link (two carriers).
    """
    common = (s.get(mesh.link_a, set()) & s.get(mesh.link_b, set())) - {mesh.link_a, mesh.link_b}
    if not common:
        raise KinematicsError(
            f"gear pair '{mesh.name}' ({mesh.link_a}–{mesh.link_b}): no common carrier — no link "
            f"is joined by turning pairs to both '{mesh.link_a}' and '{mesh.link_b}' "
            "(Penaud et al. 2012, eq 1: S_i ∩ S_j must be exactly one link)"
        )
    if len(common) > 1:
        raise KinematicsError(
            f"gear pair '{mesh.name}' ({mesh.link_a}–{mesh.link_b}): two or more carriers "
            f"{sorted(common)} — S_i ∩ S_j must be exactly one link (Penaud et al. 2012, eq 1); "
            "the turning "
            "pairs put both gears on a common axis, or two axis levels are mislabelled"
        )
    return next(iter(common))


def adjacency_table(graph: MechanismGraph) -> tuple[np.ndarray, list[list[str | None]]]:
    """Adjacency table of seed 000 §2.2.

    Returns ``(T, levels)``: ``T`` is the N×N complex gear-weight matrix (NaN where no gear pair),
    ``levels[i][j]`` the axis level of the turning pair ``i``–``j`` (``None`` where none).
    """
    n = len(graph.links)
    t = np.full((n, n), np.nan + 0j, dtype=complex)
    levels: list[list[str | None]] = [[None] * n for _ in range(n)]
    for m in graph.meshes:
        i, j = graph.index(m.link_a), graph.index(m.link_b)
        t[i, j] = m.weight_a
        t[j, i] = m.weight_b
    for jt in graph.joints:
        i, j = graph.index(jt.link_a), graph.index(jt.link_b)
        levels[i][j] = levels[j][i] = jt.axis
    return t, levels


def constraint_matrix(graph: MechanismGraph, carriers: Sequence[str]) -> np.ndarray:
    """Kinematic constraint matrix ``M`` with ``M Ω = 0`` (seed 000 §2.4, eqs 2-3).

    Row 0 fixes the frame (``ω_f = 0``); row ``l`` applies Willis to gear pair ``l`` with
    carrier ``k``: ``T(i,j)(ω_i − ω_k) + T(j,i)(ω_j − ω_k) = 0``.
    """
    n = len(graph.links)
    m = np.zeros((len(graph.meshes) + 1, n), dtype=complex)
    m[0, graph.index(graph.frame)] = 1.0
    for row, (mesh, k) in enumerate(zip(graph.meshes, carriers, strict=True), start=1):
        i, j, kk = graph.index(mesh.link_a), graph.index(mesh.link_b), graph.index(k)
        m[row, i] += mesh.weight_a
        m[row, j] += mesh.weight_b
        m[row, kk] += -mesh.weight_a - mesh.weight_b
    return m


def check_graph(graph: MechanismGraph) -> None:
    """Structural checks on a graph built from Python (the config layer checks the same)."""
    known = set(graph.links)
    problems: list[str] = []
    if len(known) != len(graph.links):
        dup = sorted({x for x in graph.links if graph.links.count(x) > 1})
        problems.append(f"links: duplicate link names {dup}")
    if graph.frame not in known:
        problems.append(f"frame: unknown link '{graph.frame}'")
    for m in graph.meshes:
        for link in (m.link_a, m.link_b):
            if link not in known:
                problems.append(f"gear pair '{m.name}': unknown link '{link}'")
        if m.link_a == m.link_b:
            problems.append(f"gear pair '{m.name}': a link cannot mesh with itself ('{m.link_a}')")
    for jt in graph.joints:
        for link in (jt.link_a, jt.link_b):
            if link not in known:
                problems.append(f"turning pair {jt.link_a}–{jt.link_b}: unknown link '{link}'")
    held = {jt.link_a for jt in graph.joints} | {jt.link_b for jt in graph.joints}
    for link in graph.links:
        if link != graph.frame and link not in held:
            problems.append(
                f"link '{link}': has no turning pair, so nothing holds it (every moving link needs "
                "a turning pair)"
            )
    if problems:
        raise KinematicsError("; ".join(problems))


@dataclass
class KinematicAnalysis:
    """Result of the seed 000 analysis of a :class:`MechanismGraph`.

    Attributes: ``graph``; ``carriers`` (reference link of each gear pair, in ``graph.meshes``
    order); ``T`` and ``levels`` (adjacency table); ``M`` (constraint matrix); ``rank``; ``dof``;
    ``singular_values`` (of the row-normalised M, for judging the rank decision);
    ``nullspace`` (an orthonormal basis of ker M, N × dof); ``axes`` (link → direction φ of
    its own axis, rad in (−π/2, π/2], the turning pair towards the frame; module docstring);
    ``physical`` (N × dof complex: a basis of the physical motions, real combinations of
    rotations about the axes, independent of any choice of inputs).
    """

    graph: MechanismGraph
    carriers: list[str]
    T: np.ndarray
    levels: list[list[str | None]]
    M: np.ndarray
    rank: int
    dof: int
    singular_values: np.ndarray
    nullspace: np.ndarray
    axes: dict[str, float]
    physical: np.ndarray

    @property
    def links(self) -> list[str]:
        return self.graph.links

    def reference_links(self) -> dict[str, str]:
        """Gear-pair name → reference link (seed 000 Tables 2 and 4)."""
        return {m.name: k for m, k in zip(self.graph.meshes, self.carriers, strict=True)}

    def adjacency_frame(self) -> pd.DataFrame:
        """The adjacency table as printed in seed 000 Tables 1 and 3.

        Gear entries read ``N∠θ°`` (``N·e^{iθ}``), turning-pair entries ``level=<axis>``.
        """
        import pandas as pd

        n = len(self.links)
        cells = [["" for _ in range(n)] for _ in range(n)]
        for i in range(n):
            for j in range(n):
                if not np.isnan(self.T[i, j]):
                    z = complex(self.T[i, j])
                    cells[i][j] = f"{abs(z):.6g}∠{np.degrees(np.angle(z)):.4g}°"
                elif self.levels[i][j] is not None:
                    cells[i][j] = f"level={self.levels[i][j]}"
        return pd.DataFrame(cells, index=self.links, columns=self.links)

    def constraint_frame(self) -> pd.DataFrame:
        """The constraint matrix M (seed 000 eq 3) with named rows and columns."""
        import pandas as pd

        rows = ["frame", *[m.name for m in self.graph.meshes]]
        return pd.DataFrame(self.M, index=rows, columns=self.links)

    def velocity_ratios(self, inputs: Sequence[str]) -> np.ndarray:
        """Velocity-ratio matrix ``Ω0`` normalised to ``inputs`` (seed 000 eq 5).

        Column ``c`` holds the (complex) angular velocity of every link when input ``c`` turns
        at unit speed and the other inputs are at rest. Raises :class:`InputError` when the
        inputs do not fix the motion.
        """
        inputs = list(inputs)
        sub = self._check_inputs(inputs)
        if self.dof == 0:
            return np.zeros((len(self.links), 0), complex)
        return _clean(self.physical @ np.linalg.inv(sub))

    def input_rows(self, inputs: Sequence[str]) -> np.ndarray:
        """Signed speed of each input about its own axis, ``Re(e^{−iφ} ω)``, in each physical
        motion (len(inputs) × dof, real)."""
        rows = [self.graph.index(x) for x in inputs]
        turn = np.exp(-1j * np.array([self.axes[x] for x in inputs]))[:, None]
        return (turn * self.physical[rows, :]).real

    def signed_speed(self, link: str, omega: complex) -> float:
        """Speed of ``link`` about its own axis, ``Re(e^{−iφ} ω)`` (module docstring), or NaN
        when its rotation is not along that axis (a link on a moving carrier of another axis)."""
        w = complex(omega) * complex(np.exp(-1j * self.axes[link]))
        return w.real if abs(w.imag) <= 1e-9 * max(abs(w), 1.0) else float("nan")

    def speeds(self, input_speeds: Mapping[str, float | np.ndarray]) -> np.ndarray:
        """Absolute angular velocities of all links, ``Ω = Ω0 Λ`` (seed 000 eq 5).

        ``input_speeds`` maps input link → signed speed (any unit, e.g. rad/s or rpm; the
        result has the same unit). Values may be arrays of equal shape (a speed profile); the
        result then has shape ``(N_links, *shape)``.
        """
        names = list(input_speeds)
        omega0 = self.velocity_ratios(names)
        lam = np.stack([np.asarray(input_speeds[x], dtype=float) for x in names])
        return np.tensordot(omega0, lam, axes=(1, 0))

    def _check_inputs(self, inputs: list[str]) -> np.ndarray:
        known = set(self.graph.links)
        for x in inputs:
            if x not in known:
                raise InputError(f"input link '{x}': unknown link (known: {', '.join(self.links)})")
            if x == self.graph.frame:
                raise InputError(f"input link '{x}': is the frame (its speed is 0 by definition)")
        if len(set(inputs)) != len(inputs):
            raise InputError(f"inputs {inputs}: a link is given twice")
        if len(inputs) != self.dof:
            raise InputError(
                f"inputs {inputs}: the mechanism has {self.dof} degree(s) of freedom, so exactly "
                f"{self.dof} input speed(s) are needed to fix the motion (got {len(inputs)})"
            )
        if self.dof == 0:
            return np.zeros((0, 0))
        sub = self.input_rows(inputs)
        s = np.linalg.svd(sub, compute_uv=False)
        if s[-1] <= 1e-9 * max(s[0], 1e-300):
            raise InputError(
                f"inputs {inputs}: do not fix the motion — their speeds about their own axes "
                "are kinematically dependent (one follows from the others), so some motion "
                "stays free; choose independent input links"
            )
        return sub


def _clean(z: np.ndarray, tol: float = 1e-12) -> np.ndarray:
    """Zero real/imaginary parts that are rounding noise (relative to the largest entry)."""
    scale = max(float(np.max(np.abs(z))), 1.0) if z.size else 1.0
    re = np.where(np.abs(z.real) < tol * scale, 0.0, z.real)
    im = np.where(np.abs(z.imag) < tol * scale, 0.0, z.imag)
    return re + 1j * im


def analyze_graph(graph: MechanismGraph) -> KinematicAnalysis:
    """Run the seed 000 kinematic analysis on a mechanism graph."""
    check_graph(graph)
    s = turning_neighbourhood(graph)
    problems: list[str] = []
    carriers: list[str] = []
    for mesh in graph.meshes:
        try:
            carriers.append(reference_link(mesh, s))
        except KinematicsError as exc:
            problems.append(str(exc))
    if problems:
        raise KinematicsError("; ".join(problems))
    t, levels = adjacency_table(graph)
    m = constraint_matrix(graph, carriers)
    # Rank of M (eq 4) on the row-normalised matrix, so the threshold does not depend on tooth
    # counts; a relative threshold of 1e-9 leaves >6 decades of margin to rounding (~1e-15).
    scaled = m / np.linalg.norm(m, axis=1, keepdims=True)
    _, sv, vh = np.linalg.svd(scaled)
    rank = int(np.sum(sv > RANK_RTOL * sv[0]))
    n = len(graph.links)
    dof = n - rank
    nullspace = vh[rank:].conj().T
    axes, physical = physical_motions(graph, carriers, m, dof)
    return KinematicAnalysis(
        graph=graph,
        carriers=carriers,
        T=t,
        levels=levels,
        M=m,
        rank=rank,
        dof=dof,
        singular_values=sv,
        nullspace=nullspace,
        axes=axes,
        physical=physical,
    )


def _half_turn(phi: float) -> float:
    """Angle folded into (−π/2, π/2] (an axis direction is defined mod π)."""
    phi = (phi + math.pi / 2) % math.pi - math.pi / 2
    return math.pi / 2 if abs(phi + math.pi / 2) < 1e-9 else phi


def turning_tree(graph: MechanismGraph) -> list[tuple[str, str]]:
    """(link, parent) of every moving link, breadth first from the frame over turning pairs."""
    nbr: dict[str, list[str]] = {x: [] for x in graph.links}
    for j in graph.joints:
        nbr[j.link_a].append(j.link_b)
        nbr[j.link_b].append(j.link_a)
    seen = {graph.frame}
    order: list[tuple[str, str]] = []
    todo = deque([graph.frame])
    while todo:
        p = todo.popleft()
        for x in nbr[p]:
            if x not in seen:
                seen.add(x)
                order.append((x, p))
                todo.append(x)
    lost = [x for x in graph.links if x not in seen]
    if lost:
        raise KinematicsError(f"links {lost} are not connected to the frame '{graph.frame}' "
                              "through turning pairs")
    return order


def axis_directions(graph: MechanismGraph, carriers: Sequence[str]) -> dict[str, float]:
    """Direction φ (rad, folded into (−π/2, π/2]) of every link's own axis: the axis of its
    turning pair towards the frame (module docstring).

    Each multiple turning pair is one axis; gear pair (a, b) on carrier k ties the axes of a–k
    and b–k by ``φ_b = φ_a + θ_a − θ_b (mod π)`` (seed 000 eq 2 with real relative speeds).
    The axis of the first link (in the order of ``links``) turning in the frame is direction
    0; an axis tied to no other by a gear pair is direction 0 too. A loop of gear pairs whose
    pitch angles disagree is a :class:`KinematicsError` naming the gear pair.
    """
    groups = multi_turning_pairs(graph)

    def group_of(x: str, y: str) -> int:
        for gi, (_lv, comp) in enumerate(groups):
            if x in comp and y in comp:
                return gi
        raise KinematicsError(f"links '{x}' and '{y}' share no turning-pair axis")

    edges: dict[int, list[tuple[int, float, str]]] = {i: [] for i in range(len(groups))}
    for mesh, k in zip(graph.meshes, carriers, strict=True):
        ga, gb = group_of(mesh.link_a, k), group_of(mesh.link_b, k)
        d = mesh.theta_a - mesh.theta_b
        edges[ga].append((gb, d, mesh.name))
        edges[gb].append((ga, -d, mesh.name))
    on_frame = {j.link_b if j.link_a == graph.frame else j.link_a for j in graph.joints
                if graph.frame in (j.link_a, j.link_b)}
    first = [x for x in graph.links if x in on_frame][:1]
    order = list(dict.fromkeys([*(group_of(x, graph.frame) for x in first),
                                *(group_of(j.link_a, j.link_b) for j in graph.joints)]))
    phi: dict[int, float] = {}
    for start in order:
        if start in phi:
            continue
        phi[start] = 0.0
        todo = deque([start])
        while todo:
            g = todo.popleft()
            for h, d, name in edges[g]:
                want = phi[g] + d
                if h not in phi:
                    phi[h] = want
                    todo.append(h)
                elif abs(math.sin(phi[h] - want)) > 1e-9:
                    raise KinematicsError(
                        f"gear pair '{name}': its pitch angles put the axis of level "
                        f"'{groups[h][0]}' at {math.degrees(_half_turn(want)):.6g}° but other "
                        f"gear pairs put it at {math.degrees(_half_turn(phi[h])):.6g}° "
                        "(Penaud et al. 2012, §2.2: θ_a + φ_a = θ_b + φ_b mod 180° in every "
                        "gear pair); "
                        "check the pitch angles")
    axes = {graph.frame: 0.0}
    for link, parent in turning_tree(graph):
        axes[link] = _half_turn(phi[group_of(link, parent)])
    return axes


def physical_motions(graph: MechanismGraph, carriers: Sequence[str], m: np.ndarray,
                     dof: int) -> tuple[dict[str, float], np.ndarray]:
    """Axis directions and a basis of the physical motions (module docstring).

    Ω = P q̇ with q̇ the real relative speeds of the turning-tree links about their axes; the
    real solutions of ``M P q̇ = 0`` (real and imaginary parts) are the physical motions. Their
    number must equal ``dof``; fewer means pitch angles that admit no motion about the axes.
    """
    axes = axis_directions(graph, carriers)
    tree = turning_tree(graph)
    idx = {x: i for i, x in enumerate(graph.links)}
    p = np.zeros((len(graph.links), len(tree)), complex)
    for i, (link, parent) in enumerate(tree):
        p[idx[link]] = p[idx[parent]]
        p[idx[link], i] += np.exp(1j * axes[link])
    rows = m[1:] @ p
    rows = rows / np.maximum(np.abs(rows).max(axis=1, keepdims=True), 1e-300)
    real = np.vstack([rows.real, rows.imag])
    if real.size:
        _, sv, vh = np.linalg.svd(real)
        rank = int(np.sum(sv > RANK_RTOL * max(sv[0], 1e-300)))
    else:
        rank, vh = 0, np.eye(len(tree))
    basis = vh[rank:].T
    if basis.shape[1] != dof:
        raise KinematicsError(
            f"mechanism '{graph.name}': the pitch angles admit {basis.shape[1]} motion(s) "
            f"about the turning-pair axes but rank(M) leaves {dof} degree(s) of freedom "
            "(Penaud et al. 2012, §2.2): check the pitch angles of the bevel gear pairs")
    return axes, _clean(p @ basis)
