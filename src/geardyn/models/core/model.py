"""The general mechanism model on the shared assembly (SI units).

A :class:`CoreModel` holds, in its :class:`~geardyn.models.core.assembly.Assembly`,

* the generalised coordinates ``q`` (rad): one per moving mechanism link — its rotation
  relative to the link it turns in (its *parent* in the tree of turning pairs, the frame for a
  shaft in the housing) — and one per extra rotor (motor, bucket wheel);
* the constant mass matrix ``M`` (kinetic energy ½ q̇ᵀ M q̇, one inertia block per body);
* linear rank-one elements (:class:`Spring`: torsional shafts and supports, k a aᵀ);
* the carrier frames of the lateral model (G, K_Ω blocks);
* the meshes at their mean stiffness (rank-one, kind ``mesh``);

and beside it the mesh elements (:class:`MeshElement`): rank-one springs along the line of
action whose deflection δ = aᵀq + e(X) is the Willis row of the gear pair relative to its
carrier, scaled by the base radii (seed 000 eq 1-2: for a rigid-body motion δ = 0, so the
rigid-body modes are the kinematic nullspace, eq 5); stiffness k(X) and error e(X) are
tabulated over the mesh coordinate X = bᵀq (mesh cycles of gear a relative to the carrier).

``K(t) = K₀ + Σ_m k_m(X_m) a_m a_mᵀ``; ``C = C₀ + Σ_m c_m a_m a_mᵀ``; ``G`` and ``K_Ω`` of the
carrier frames of the lateral model (0 for the torsional model). :meth:`CoreModel.system`
gives the integrator's :class:`~geardyn.solve.integrate.LinearSystem`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from geardyn.errors import InputError
from geardyn.models.core.assembly import Assembly, RankOne
from geardyn.solve.integrate import LinearSystem, MassSchedule, VarSprings

#: Kind of the meshes' rank-one elements in the assembly.
MESH = "mesh"


@dataclass
class Body:
    """A rotating body: ``rotation`` is the row h with θ = h·q (rad) about its own axis."""

    name: str
    kind: str  # "link" | "rotor"
    rotation: np.ndarray
    inertia: float  # kg·m², polar
    dof: int | None = None  # index of the body's own coordinate q


class Spring(RankOne):
    """Linear rank-one element of the assembly: torque/force −k (aᵀq) a, viscous −c (aᵀq̇) a;
    ``kind``: shaft | support | bearing."""


@dataclass
class MeshElement:
    """Gear mesh along its line of action relative to its carrier (seed 000 eq 1).

    ``a``: deflection row (m/rad), δ = a·q + e(X); ``b``: mesh-cycle row, X = b·q + x0;
    ``k``/``e`` tables over ``k_period``/``e_period`` mesh cycles (N/m, m); ``c`` viscous
    damping along the line of action (N·s/m). ``psi`` is the direction (rad, sketch plane) of
    the tooth axis used to make the complex Willis row real. The mesh is also a rank-one
    element (kind ``mesh``) of the model's assembly at its mean stiffness and damping, for
    K_mean and C (k a aᵀ does not depend on the orientation of a).
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
    """Assembled model over the shared :class:`Assembly` (named DOFs, inertia blocks, linear
    rank-one elements, the meshes at their mean stiffness, one rotating frame per carrier of
    the lateral model); ``link_velocity`` (complex, links × n) maps q̇ to the seed 000 angular
    velocities Ω of the mechanism links (frame row 0)."""

    assembly: Assembly
    meshes: list[MeshElement]
    bodies: dict[str, Body]
    links: list[str]
    link_velocity: np.ndarray
    frame: str = ""

    @property
    def dof_names(self) -> list[str]:
        return self.assembly.names

    @property
    def n(self) -> int:
        return self.assembly.n

    @property
    def M(self) -> np.ndarray:  # noqa: N802 (the field's name)
        """Mass matrix (kinetic energy ½ q̇ᵀ M q̇; kg·m², kg)."""
        return self.assembly.matrix("M")  # type: ignore[return-value]

    @property
    def springs(self) -> list[Spring]:
        """The linear rank-one elements (shafts, supports, bearings), without the meshes."""
        return [e for e in self.assembly.rank_one if e.kind != MESH]  # type: ignore[misc]

    @property
    def rotating(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(rate row r, G, K_Ω) per carrier frame of the lateral model: Ω = r·q̇."""
        return [(r, g, k) for _name, r, g, k in self.assembly.frame_terms()]

    def mass_matrix(self) -> np.ndarray:
        return self.M

    def gyroscopic_matrix(self) -> np.ndarray:
        """Σ G of the carrier frames (lateral model; 0 for the torsional model). Each frame's
        term is Ω G q̇ at its own carrier speed: see :attr:`rotating`."""
        return self.assembly.matrix("G")  # type: ignore[return-value]

    def centripetal_matrix(self) -> np.ndarray:
        """Σ K_Ω of the carrier frames (the −Ω² K_Ω q term, lateral model)."""
        return self.assembly.matrix("K_omega")  # type: ignore[return-value]

    def constant_stiffness(self) -> np.ndarray:
        """K₀: the linear elements (shafts, supports, bearings), without the meshes."""
        kinds = sorted({e.kind for e in self.assembly.rank_one if e.kind != MESH}
                       | {b.kind for b in self.assembly.blocks if "K" in b.mats})
        return self.assembly.matrix("K", kinds)  # type: ignore[return-value]

    def mesh_vectors(self) -> np.ndarray:
        """Deflection rows a_m (meshes × n, m/rad)."""
        return np.array([m.a for m in self.meshes]).reshape(len(self.meshes), self.n)

    def mesh_indices(self) -> list[int]:
        """Indices of the meshes among the assembly's rank-one elements."""
        return [i for i, e in enumerate(self.assembly.rank_one) if e.kind == MESH]

    def stiffness_matrix(self, mesh_k: np.ndarray | None = None) -> np.ndarray:
        """K = K₀ + Σ k_m a_m a_mᵀ with the mean mesh stiffnesses (or ``mesh_k``, N/m)."""
        if mesh_k is None:
            return self.assembly.matrix("K")  # type: ignore[return-value]
        a = self.mesh_vectors()
        return self.constant_stiffness() + (a.T * np.asarray(mesh_k)) @ a

    def damping_matrix(self, rayleigh: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
        """C = C₀ (shaft dampers) + Σ c_m a_m a_mᵀ + α M + β K_mean (seed 003 eq 1.16)."""
        return (rayleigh[0] * self.M + rayleigh[1] * self.stiffness_matrix()
                + self.assembly.matrix("C"))

    def body(self, name: str) -> Body:
        if name not in self.bodies:
            raise InputError(f"unknown body '{name}' (bodies: {', '.join(self.bodies)})")
        return self.bodies[name]

    def rotation_matrix(self) -> np.ndarray:
        """Rows h of every body (bodies × n): θ = R q."""
        return np.array([b.rotation for b in self.bodies.values()])

    def mesh_rows(self, contact_loss: bool = False) -> list[dict]:
        """The meshes as variable-spring rows (:meth:`VarSprings.build`), their damping in the
        rows."""
        return [dict(a=m.a, b=m.b, x0=m.x0, k=m.k, k_period=m.k_period, e=m.e,
                     e_period=m.e_period, c=m.c, contact_loss=contact_loss or m.contact_loss)
                for m in self.meshes]

    def variable_springs(self, contact_loss: bool = False) -> VarSprings:
        """The meshes as the integrator's variable springs (their damping in the rows)."""
        return VarSprings.build(self.mesh_rows(contact_loss), self.n)

    def system(self, rayleigh: tuple[float, float] = (0.0, 0.0), drives: list[dict] | None = None,
               force_t: np.ndarray | None = None, force: np.ndarray | None = None,
               contact_loss: bool = False, mass_schedule: MassSchedule | None = None,
               gyroscopic: bool = False, modal_damping: float = 0.0,
               support_damping: Mapping[str, float] | None = None) -> LinearSystem:
        """Integrator system (:func:`geardyn.models.core.system.linear_system` on the model's
        assembly): M, C₀ (shaft dampers + Rayleigh on K_mean + modal damping ζ + dampers on
        named DOFs), K₀ (linear elements) and the meshes as variable springs carrying their own
        damping; ``mass_schedule`` optional (M_ii as a function of an angle, e.g. the bucket
        wheel's ore load); ``gyroscopic``: Ω G q̇ − Ω² K_Ω q of every carrier frame at its
        current speed (seed 003 eq 3.1)."""
        from geardyn.models.core.system import linear_system

        return linear_system(self.assembly, self.mesh_rows(contact_loss), self.mesh_indices(),
                             rayleigh=rayleigh, modal_damping=modal_damping,
                             support_damping=support_damping, drives=drives, force_t=force_t,
                             force=force, mass_schedule=mass_schedule, gyroscopic=gyroscopic)
