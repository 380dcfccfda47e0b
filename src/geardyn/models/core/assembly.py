"""The one assembly of every dynamic model: named DOFs, linear elements, matrices (SI units).

Every builder (the Lin & Parker planetary stages, the graph → model of any mechanism, the FE
shaft lines) registers its bodies or nodes here and stamps its linear elements:

* :meth:`Assembly.add_dofs` — a body or FE node with named DOFs (``sun.x``, ``sun.u``,
  ``input.n3.ry``) and, optionally, a diagonal mass per DOF (kg, or kg·m² for rotations);
* :meth:`Assembly.add_rank_one` — a rank-one spring/damper ``k a aᵀ``, ``c a aᵀ`` along a
  deflection row ``a`` (δ = aᵀq; supports, torsional shafts, planet bearings, meshes at their
  mean stiffness; seed 003 notes §2.3);
* :meth:`Assembly.add_block` — an element matrix stamped on a list of DOFs (Timoshenko shaft
  elements, discs: ``K_e``, ``M_e``, ``G_e``, ``C_e``);
* :meth:`Assembly.add_frame` — a rotating frame turning at Ω = r·q̇ (a planetary carrier):
  the blocks stamped with ``frame=`` carry its gyroscopic ``G`` and centripetal ``K_omega``
  matrices, the Ω G q̇ − Ω² K_Ω q terms of the bodies described in that frame (seed 003
  eq 3.1, eqs 3.4-3.8).

Connecting elements with state (time-varying meshes, nonlinear bearings) and drives are not
linear: the builders hand them to the integrators in ``geardyn.solve`` with the matrices
produced here. Dense matrices by default (lumped models have ≤ a few hundred DOFs);
``sparse=True`` gives CSR for FE lines.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from geardyn.errors import ConfigError

MATRICES = ("K", "M", "C", "G", "K_omega")


@dataclass
class RankOne:
    """Linear rank-one element: force −k (aᵀq) a − c (aᵀq̇) a (N or N·m)."""

    name: str
    kind: str
    k: float
    a: np.ndarray
    c: float = 0.0


@dataclass
class Block:
    """Element matrices (``K``, ``M``, ``C``, ``G``, ``K_omega``; d × d or None) on the DOFs
    ``dofs``; ``frame``: the rotating frame whose rate multiplies ``G`` (and Ω² ``K_omega``),
    "" for none."""

    name: str
    kind: str
    dofs: np.ndarray
    mats: dict[str, np.ndarray] = field(default_factory=dict)
    frame: str = ""


@dataclass
class Assembly:
    """Named DOFs and the linear elements stamped on them."""

    names: list[str] = field(default_factory=list)
    point_mass: list[float] = field(default_factory=list)
    rank_one: list[RankOne] = field(default_factory=list)
    blocks: list[Block] = field(default_factory=list)
    frames: dict[str, np.ndarray] = field(default_factory=dict)
    _index: dict[str, int] = field(default_factory=dict, repr=False)

    # ---- DOFs ---------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.names)

    def add_dofs(self, owner: str, labels: Sequence[str],
                 masses: Sequence[float] | None = None) -> list[int]:
        """Register DOFs ``owner.label`` (diagonal masses, default 0) and return their indices."""
        if masses is not None and len(masses) != len(labels):
            raise ValueError(f"{owner}: {len(labels)} DOF labels but {len(masses)} masses")
        out = []
        for j, lab in enumerate(labels):
            name = f"{owner}.{lab}" if owner else lab
            if name in self._index:
                raise ConfigError(f"DOF '{name}' is defined twice (body or node names must be "
                                  "unique)")
            m = 0.0 if masses is None else float(masses[j])
            if not np.isfinite(m) or m < 0:
                raise ConfigError(f"{name}: mass must be finite and ≥ 0, got {m!r}")
            self._index[name] = len(self.names)
            out.append(len(self.names))
            self.names.append(name)
            self.point_mass.append(m)
        return out

    def dof(self, name: str) -> int:
        """Index of a DOF by name."""
        if name not in self._index:
            raise ConfigError(f"unknown DOF '{name}' (there are {self.n}: "
                              f"{', '.join(self.names[:12])}{' …' if self.n > 12 else ''})")
        return self._index[name]

    def row(self, entries: Mapping[int | str, float]) -> np.ndarray:
        """Deflection row a (length n) from {DOF index or name: coefficient}; repeated
        DOFs add up."""
        a = np.zeros(self.n)
        for key, coef in entries.items():
            a[self.dof(key) if isinstance(key, str) else int(key)] += coef
        return a

    # ---- elements -----------------------------------------------------------------------
    def add_rank_one(self, element: RankOne) -> RankOne:
        """Append a rank-one element (its row must have the current length n)."""
        if element.a.shape != (self.n,):
            raise ValueError(f"element '{element.name}': row of length {element.a.shape} for "
                             f"{self.n} DOFs (add every DOF before the elements)")
        self.rank_one.append(element)
        return element

    def add_frame(self, name: str, rate: np.ndarray) -> None:
        """Register a rotating frame turning at Ω = rate·q̇ (rad/s; ``rate`` of length n)."""
        if name in self.frames:
            raise ConfigError(f"rotating frame '{name}' is defined twice")
        rate = np.asarray(rate, float)
        if rate.shape != (self.n,):
            raise ValueError(f"frame '{name}': rate row of length {rate.shape} for {self.n} DOFs")
        self.frames[name] = rate

    def add_block(self, name: str, kind: str, dofs: Iterable[int | str],
                  frame: str = "", **mats: np.ndarray | None) -> Block:
        """Stamp element matrices (keywords among K, M, C, G, K_omega) on ``dofs``; ``frame``:
        a frame of :meth:`add_frame` that the block's G and K_omega turn with."""
        if frame and frame not in self.frames:
            raise ValueError(f"element '{name}': unknown rotating frame '{frame}'")
        idx = np.array([self.dof(d) if isinstance(d, str) else int(d) for d in dofs], np.int64)
        given = {}
        for key, m in mats.items():
            if key not in MATRICES:
                raise ValueError(f"element '{name}': unknown matrix '{key}' (one of {MATRICES})")
            if m is None:
                continue
            m = np.asarray(m, float)
            if m.shape != (idx.size, idx.size):
                raise ValueError(f"element '{name}': {key} is {m.shape} for {idx.size} DOFs")
            given[key] = m
        block = Block(name, kind, idx, given, frame)
        self.blocks.append(block)
        return block

    def add_mapped(self, name: str, kind: str, d: np.ndarray, frame: str = "",
                   **mats: np.ndarray | None) -> Block:
        """Stamp Dᵀ X D for element matrices X (r × r, keywords as :meth:`add_block`) given in
        the element's own coordinates y = D q (``d``: r × n), on the DOFs where D is non-zero
        (a body's kinetic energy ½ ẏᵀ M_e ẏ, its rotating-frame terms)."""
        d = np.atleast_2d(np.asarray(d, float))
        if d.shape[1] != self.n:
            raise ValueError(f"element '{name}': map of {d.shape[1]} columns for {self.n} DOFs")
        cols = np.flatnonzero(np.abs(d).max(axis=0) > 0.0)
        dc = d[:, cols]
        return self.add_block(name, kind, cols, frame=frame,
                              **{k: None if x is None else dc.T @ np.asarray(x, float) @ dc
                                 for k, x in mats.items()})

    # ---- matrices -----------------------------------------------------------------------
    def _rank_one_sum(self, attr: str, kinds: Sequence[str] | None) -> np.ndarray:
        out = np.zeros((self.n, self.n))
        for e in self.rank_one:
            w = getattr(e, attr)
            if w != 0.0 and (kinds is None or e.kind in kinds):
                out += w * np.outer(e.a, e.a)
        return out

    def block_matrix(self, key: str, kinds: Sequence[str] | None = None, sparse: bool = False,
                     frame: str | None = None) -> np.ndarray | sp.csr_matrix:
        """Σ of the blocks' ``key`` matrices over ``kinds`` (all if None) and ``frame``
        (any if None), without rank-one elements or point masses."""
        rows, cols, vals = [], [], []
        for b in self.blocks:
            m = b.mats.get(key)
            if m is None or (kinds is not None and b.kind not in kinds) or (
                    frame is not None and b.frame != frame):
                continue
            rows.append(np.repeat(b.dofs, b.dofs.size))
            cols.append(np.tile(b.dofs, b.dofs.size))
            vals.append(m.ravel())
        if not rows:
            return sp.csr_matrix((self.n, self.n)) if sparse else np.zeros((self.n, self.n))
        coo = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                            shape=(self.n, self.n))
        return coo.tocsr() if sparse else coo.toarray()

    def matrix(self, key: str, kinds: Sequence[str] | None = None, sparse: bool = False,
               frame: str | None = None) -> np.ndarray | sp.csr_matrix:
        """Assembled ``K``, ``M``, ``C``, ``G`` or ``K_omega`` over the elements of ``kinds``
        (all if None): K = Σ k a aᵀ + Σ K_e, C = Σ c a aᵀ + Σ C_e, M = diag(point masses) +
        Σ M_e, G = Σ G_e, K_Ω = Σ K_Ω,e. ``frame``: only the blocks of that rotating frame
        (no rank-one elements, no point masses)."""
        if key not in MATRICES:
            raise ValueError(f"unknown matrix '{key}' (one of {MATRICES})")
        out = self.block_matrix(key, kinds, sparse, frame)
        extra = None
        if key == "M" and kinds is None and frame is None:
            extra = np.diag(np.asarray(self.point_mass, float))
        elif key in ("K", "C") and self.rank_one and frame is None:
            extra = self._rank_one_sum("k" if key == "K" else "c", kinds)
        if extra is None:
            return out
        return (out + sp.csr_matrix(extra)).tocsr() if sparse else out + extra

    def rows(self, kinds: Sequence[str] | None = None) -> np.ndarray:
        """Deflection rows of the rank-one elements of ``kinds`` (elements × n)."""
        sel = [e.a for e in self.rank_one if kinds is None or e.kind in kinds]
        return np.array(sel).reshape(len(sel), self.n)

    def frame_terms(self) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
        """(name, rate row r, G, K_Ω) of every rotating frame (dense): the Ω G q̇ − Ω² K_Ω q
        terms at Ω = r·q̇ (seed 003 eq 3.1)."""
        return [(name, rate, self.matrix("G", frame=name), self.matrix("K_omega", frame=name))
                for name, rate in self.frames.items()]
