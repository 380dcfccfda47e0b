"""Assembly core: bodies with named DOFs, linear elements and mesh elements (SI units).

A :class:`CoreModel` holds

* the generalised coordinates ``q`` (rad): one per moving mechanism link — its rotation
  relative to the link it turns in (its *parent* in the tree of turning pairs, the frame for a
  shaft in the housing) — and one per extra rotor (motor, bucket wheel);
* the constant mass matrix ``M`` (kinetic energy ½ q̇ᵀ M q̇);
* linear rank-one elements (:class:`Spring`: torsional shafts and supports, k a aᵀ);
* mesh elements (:class:`MeshElement`): rank-one springs along the line of action whose
  deflection δ = aᵀq + e(X) is the Willis row of the gear pair relative to its carrier, scaled
  by the base radii (seed 000 eq 1-2: for a rigid-body motion δ = 0, so the rigid-body modes
  are the kinematic nullspace, eq 5); stiffness k(X) and error e(X) are tabulated over the mesh
  coordinate X = bᵀq (mesh cycles of gear a relative to the carrier).

``K(t) = K₀ + Σ_m k_m(X_m) a_m a_mᵀ``; ``C = C₀ + Σ_m c_m a_m a_mᵀ``; ``G`` and ``K_Ω`` of the
carrier frames of the lateral model (0 for the torsional model). :meth:`CoreModel.system`
gives the integrator's :class:`~geardyn.solve.integrate.LinearSystem`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from geardyn.errors import InputError
from geardyn.solve.integrate import Drives, LinearSystem, MassSchedule, VarSprings


@dataclass
class Body:
    """A rotating body: ``rotation`` is the row h with θ = h·q (rad) about its own axis."""

    name: str
    kind: str  # "link" | "rotor"
    rotation: np.ndarray
    inertia: float  # kg·m², polar
    dof: int | None = None  # index of the body's own coordinate q


@dataclass
class Spring:
    """Linear rank-one element: torque/force −k (aᵀq) a, viscous −c (aᵀq̇) a."""

    name: str
    kind: str  # "shaft" | "support"
    k: float
    a: np.ndarray
    c: float = 0.0


@dataclass
class MeshElement:
    """Gear mesh along its line of action relative to its carrier (seed 000 eq 1).

    ``a``: deflection row (m/rad), δ = a·q + e(X); ``b``: mesh-cycle row, X = b·q + x0;
    ``k``/``e`` tables over ``k_period``/``e_period`` mesh cycles (N/m, m); ``c`` viscous
    damping along the line of action (N·s/m). ``psi`` is the direction (rad, sketch plane) of
    the tooth axis used to make the complex Willis row real.
    """

    name: str
    link_a: str
    link_b: str
    carrier: str
    teeth_a: int
    teeth_b: int
    a: np.ndarray
    b: np.ndarray
    k: np.ndarray
    k_period: float = 1.0
    e: np.ndarray = field(default_factory=lambda: np.zeros(1))
    e_period: float = 1.0
    c: float = 0.0
    contact_loss: bool = False
    x0: float = 0.0
    base_radius_a: float = 0.0
    base_radius_b: float = 0.0
    psi: float = 0.0
    stage: str | None = None

    @property
    def k_mean(self) -> float:
        """Mean stiffness over the table (N/m)."""
        return float(np.mean(self.k))


@dataclass
class CoreModel:
    """Assembled model; ``link_velocity`` (complex, links × n) maps q̇ to the seed 000 angular
    velocities Ω of the mechanism links (frame row 0)."""

    dof_names: list[str]
    M: np.ndarray
    springs: list[Spring]
    meshes: list[MeshElement]
    bodies: dict[str, Body]
    links: list[str]
    link_velocity: np.ndarray
    frame: str = ""
    rotating: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=list)
    """(rate row r, G, K_Ω) per carrier frame of the lateral model: Ω = r·q̇."""

    @property
    def n(self) -> int:
        return len(self.dof_names)

    def mass_matrix(self) -> np.ndarray:
        return self.M.copy()

    def gyroscopic_matrix(self) -> np.ndarray:
        """Σ G of the carrier frames (lateral model; 0 for the torsional model). Each frame's
        term is Ω G q̇ at its own carrier speed: see :attr:`rotating`."""
        g = np.zeros((self.n, self.n))
        for _r, gg, _k in self.rotating:
            g += gg
        return g

    def centripetal_matrix(self) -> np.ndarray:
        """Σ K_Ω of the carrier frames (the −Ω² K_Ω q term, lateral model)."""
        k = np.zeros((self.n, self.n))
        for _r, _g, kk in self.rotating:
            k += kk
        return k

    def constant_stiffness(self) -> np.ndarray:
        """K₀: the linear elements (shafts, supports), without the meshes."""
        k = np.zeros((self.n, self.n))
        for s in self.springs:
            k += s.k * np.outer(s.a, s.a)
        return k

    def mesh_vectors(self) -> np.ndarray:
        """Deflection rows a_m (meshes × n, m/rad)."""
        return np.array([m.a for m in self.meshes]).reshape(len(self.meshes), self.n)

    def stiffness_matrix(self, mesh_k: np.ndarray | None = None) -> np.ndarray:
        """K = K₀ + Σ k_m a_m a_mᵀ with the mean mesh stiffnesses (or ``mesh_k``, N/m)."""
        km = np.array([m.k_mean for m in self.meshes]) if mesh_k is None else np.asarray(mesh_k)
        a = self.mesh_vectors()
        return self.constant_stiffness() + (a.T * km) @ a

    def damping_matrix(self, rayleigh: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
        """C = C₀ (shaft dampers) + Σ c_m a_m a_mᵀ + α M + β K_mean (seed 003 eq 1.16)."""
        c = rayleigh[0] * self.M + rayleigh[1] * self.stiffness_matrix()
        for s in self.springs:
            c += s.c * np.outer(s.a, s.a)
        a = self.mesh_vectors()
        cm = np.array([m.c for m in self.meshes])
        return c + (a.T * cm) @ a

    def body(self, name: str) -> Body:
        if name not in self.bodies:
            raise InputError(f"unknown body '{name}' (bodies: {', '.join(self.bodies)})")
        return self.bodies[name]

    def rotation_matrix(self) -> np.ndarray:
        """Rows h of every body (bodies × n): θ = R q."""
        return np.array([b.rotation for b in self.bodies.values()])

    def variable_springs(self, contact_loss: bool = False) -> VarSprings:
        """The meshes as the integrator's variable springs (damping in C₀, not here)."""
        rows = [dict(a=m.a, b=m.b, x0=m.x0, k=m.k, k_period=m.k_period, e=m.e,
                     e_period=m.e_period, c=m.c, contact_loss=contact_loss or m.contact_loss)
                for m in self.meshes]
        return VarSprings.build(rows, self.n)

    def system(self, rayleigh: tuple[float, float] = (0.0, 0.0), drives: list[dict] | None = None,
               force_t: np.ndarray | None = None, force: np.ndarray | None = None,
               contact_loss: bool = False, mass_schedule: MassSchedule | None = None,
               gyroscopic: bool = False) -> LinearSystem:
        """Integrator system: M, C₀ (shafts + Rayleigh on K_mean), K₀ (linear elements) and the
        meshes as variable springs carrying their own damping; ``mass_schedule`` optional
        (M_ii as a function of an angle, e.g. the bucket wheel's ore load); ``gyroscopic``:
        Ω G q̇ − Ω² K_Ω q of every carrier frame at its current speed (seed 003 eq 3.1)."""
        c0 = rayleigh[0] * self.M + rayleigh[1] * self.stiffness_matrix()
        for s in self.springs:
            c0 += s.c * np.outer(s.a, s.a)
        n = self.n
        frames = self.rotating if gyroscopic else []
        return LinearSystem(
            self.M.copy(), c0, self.constant_stiffness(), self.variable_springs(contact_loss),
            Drives.build(drives or []),
            np.zeros(0) if force_t is None else np.asarray(force_t, float),
            np.zeros((0, n)) if force is None else np.asarray(force, float),
            mass_schedule or MassSchedule(), list(self.dof_names),
            gyro_g=np.array([g for _r, g, _k in frames]).reshape(len(frames), n, n),
            gyro_k=np.array([k for _r, _g, k in frames]).reshape(len(frames), n, n),
            gyro_rate=np.array([r for r, _g, _k in frames]).reshape(len(frames), n),
        )
