"""Lumped-parameter planetary model assembled from rank-one spring elements (SI units).

Formulation of Lin & Parker (1999) as cleaned up in seed 003 notes §2.3 (thesis eqs 3.2-3.24
with the errata of the notes applied): every body has three DOF,

- central members (sun, ring, carrier): ``x``, ``y`` (m, carrier-fixed frame) and
  ``u = r θ`` (m; r is the base radius for sun and ring, the planet-circle radius for the
  carrier; seed 003 eq 3.3);
- planets: ``zeta`` (radial), ``eta`` (tangential) (m, carrier frame) and ``u = r_b θ`` (m).

Each spring e contributes ``k_e a_e a_eᵀ`` where ``a_e`` is its deflection vector
(δ_e = a_eᵀ q, positive in compression):

- sun–planet mesh  δ = −x_s sinψ_s + y_s cosψ_s + u_s − ζ sinα_s − η cosα_s + u_p, ψ_s = ψ − α_s
- ring–planet mesh δ = −x_r sinψ_r + y_r cosψ_r + u_r + ζ sinα_r − η cosα_r − u_p, ψ_r = ψ + α_r
- planet bearing   δ_ζ = x_c cosψ + y_c sinψ − ζ,  δ_η = −x_c sinψ + y_c cosψ + u_c − η
- central bearings on x, y and a torsional support on u (given in N·m/rad, divided by r²).

Bodies outside the planetary stages (a motor rotor, a bucket wheel) are torsional bodies with
one DOF ``theta`` (rad). Shafts couple any two bodies torsionally (N·m/rad on the rotation
angles) and, for central members, flexurally (N/m between x and between y).

Reductions (seed 003 model B, seed 004 ``cd`` = 1/2) are linear constraints q_full = T q:
``torsional`` keeps the u DOF (central x, y and planet ζ fixed; planet η follows the carrier,
η = u_c, i.e. rigid planet bearings, which puts N m_p on the carrier, seed 003 eq 4.2);
``transverse`` keeps x, y, ζ, η. Matrices and deflection vectors are transformed with T.

The model is a builder on the shared :class:`~geardyn.models.core.assembly.Assembly`: the
bodies' DOFs with their masses, every spring a rank-one element (:class:`Spring` keeps the
stage, body, planet and bin labels), and one rotating frame per stage (the carrier's) whose
blocks hold the G and K_Ω of the stage's members; the integrator system comes from
:func:`geardyn.models.core.system.linear_system` (``dynamics.build_system``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from geardyn.errors import ConfigError
from geardyn.models.core.assembly import Assembly, RankOne

if TYPE_CHECKING:
    from geardyn.solve.modal import ModalResult

CENTRAL = ("carrier", "ring", "sun")  # block order of seed 003 eq 3.26 / Table 3.4


@dataclass
class Body:
    """A rigid body of the model. ``kind``: ``central``, ``planet`` or ``rotor``."""

    name: str
    kind: str
    mass: float  # kg
    inertia: float  # kg·m²
    radius: float  # m (base radius; planet circle for the carrier; 1 for rotors)
    dofs: list[int] = field(default_factory=list)
    stage: str = ""
    teeth: int = 0


@dataclass
class Spring(RankOne):
    """Rank-one spring of the assembly (force −k δ a, δ = aᵀ q, N/m along its deflection) with
    its planetary labels. ``kind``: bearing | support_u | planet_bearing | mesh_sun |
    mesh_ring | shaft."""

    stage: str = ""
    body: str = ""
    planet: int = 0  # 1-based planet index for meshes and planet bearings
    bin: str = ""  # Table 3.5 style label


@dataclass
class StageInfo:
    """Geometry of one planetary stage needed for mesh phasing and outputs."""

    name: str
    psi: np.ndarray  # planet angles, rad
    alpha_s: float
    alpha_r: float
    r_sun: float
    r_ring: float
    r_planet: float
    r_carrier: float
    z_sun: int
    z_ring: int
    z_planet: int
    bodies: dict[str, str]  # role -> full body name


@dataclass
class PlanetaryModel:
    """Assembled model: bodies and stages over the shared :class:`Assembly` (full coordinates:
    DOF names, diagonal masses, the springs as rank-one elements, G and K_Ω as blocks of one
    rotating frame per stage).

    ``T`` maps reduced to full coordinates (identity for the coupled model); use the
    ``reduced_*`` accessors for the matrices actually solved.
    """

    bodies: dict[str, Body]
    stages: dict[str, StageInfo]
    assembly: Assembly
    reduction: str = "none"
    T: np.ndarray | None = None

    # ---- the assembly's contents (full coordinates) -----------------------------------
    @property
    def dof_names(self) -> list[str]:
        return self.assembly.names

    @property
    def mass_diag(self) -> np.ndarray:
        """Diagonal masses (kg; m = J/r² on the u DOFs)."""
        return np.asarray(self.assembly.point_mass, float)

    @property
    def springs(self) -> list[Spring]:
        """The rank-one springs, in assembly order."""
        return self.assembly.rank_one  # type: ignore[return-value]

    @property
    def gyro(self) -> np.ndarray:
        """G (full coords) of all stages, seed 003 eqs 3.4-3.5."""
        return self.assembly.matrix("G")  # type: ignore[return-value]

    @property
    def k_omega(self) -> np.ndarray:
        """Centripetal K_Ω (full coords) of all stages, eqs 3.6-3.8 corrected."""
        return self.assembly.matrix("K_omega")  # type: ignore[return-value]

    # ---- matrices -------------------------------------------------------------------
    @property
    def n_full(self) -> int:
        return len(self.dof_names)

    @property
    def transform(self) -> np.ndarray:
        return np.eye(self.n_full) if self.T is None else self.T

    @property
    def names(self) -> list[str]:
        """Names of the solved (reduced) DOF."""
        if self.T is None:
            return list(self.dof_names)
        keep = [j for j in range(self.T.shape[1])]
        out = []
        for j in keep:
            col = self.T[:, j]
            i = int(np.argmax(np.abs(col)))
            out.append(self.dof_names[i])
        return out

    def mass_matrix(self) -> np.ndarray:
        t = self.transform
        return t.T @ self.assembly.matrix("M") @ t

    def stiffness_matrix(self, kinds: tuple[str, ...] | None = None) -> np.ndarray:
        t = self.transform
        return t.T @ self.assembly.matrix("K", kinds) @ t

    def spring_vectors(self) -> np.ndarray:
        """Deflection vectors in solved coordinates, one row per spring."""
        a = np.array([s.a for s in self.springs])
        return a @ self.transform

    def gyroscopic_matrix(self) -> np.ndarray:
        t = self.transform
        return t.T @ self.gyro @ t

    def centripetal_matrix(self) -> np.ndarray:
        t = self.transform
        return t.T @ self.k_omega @ t

    def dof(self, name: str) -> int:
        """Index of a solved DOF by name (e.g. ``sun.u`` or ``test.sun.u``)."""
        names = self.names
        if name not in names:
            raise ConfigError(f"unknown DOF '{name}' (available: {', '.join(names)})")
        return names.index(name)

    def body(self, name: str) -> Body:
        if name not in self.bodies:
            raise ConfigError(f"unknown body '{name}' (bodies: {', '.join(self.bodies)})")
        return self.bodies[name]

    def rotation_vector(self, body: str) -> np.ndarray:
        """Row vector c with θ_body = c q (rad) in solved coordinates."""
        b = self.body(body)
        v = np.zeros(self.n_full)
        v[b.dofs[-1]] = 1.0 / b.radius
        return v @ self.transform

    def strain_energy_table(self, res: ModalResult) -> tuple[list[str], np.ndarray]:
        """Strain energy of the modes ``res`` in the Hammami 2015 Table 3.5 layout
        (:func:`geardyn.models.planetary.modal.strain_energy_table`)."""
        from geardyn.models.planetary.modal import strain_energy_table

        return strain_energy_table(self, res)


@dataclass
class StageSpec:
    """Parameters of one planetary stage (SI units; angles in rad).

    Bearing stiffnesses in N/m act on x and y; ``*_torsional`` supports are N·m/rad. Planet
    bearings act radially and tangentially with ``planet_bearing`` N/m (seed 003 eqs 3.14-3.16).
    Mesh stiffnesses are mean values along the line of action (N/m).
    """

    name: str
    n_planets: int
    planet_angles: list[float]
    sun: dict[str, float]
    ring: dict[str, float]
    carrier: dict[str, float]
    planet: dict[str, float]
    alpha_s: float
    alpha_r: float
    k_sun_mesh: float
    k_ring_mesh: float
    planet_bearing: float
    z_sun: int = 0
    z_ring: int = 0
    z_planet: int = 0
    prefix: bool = True


@dataclass
class ShaftSpec:
    """A shaft between two bodies: torsional (N·m/rad) and flexural (N/m, x and y)."""

    name: str
    a: str
    b: str
    torsional: float = 0.0
    flexural: float = 0.0


@dataclass
class RotorSpec:
    """A torsional-only body (motor rotor, wheel): inertia kg·m², support N·m/rad."""

    name: str
    inertia: float
    support: float = 0.0


def assemble(
    stages: list[StageSpec],
    shafts: list[ShaftSpec] | None = None,
    rotors: list[RotorSpec] | None = None,
    reduction: str = "none",
) -> PlanetaryModel:
    """Assemble the model on the shared :class:`Assembly` (seed 003 eqs 3.2-3.26; notes §2.3
    rank-one form): each body's DOFs with their masses, each spring a rank-one element, and per
    stage a rotating frame (the carrier's) with the G and K_Ω blocks of its members."""
    shafts = shafts or []
    rotors = rotors or []
    asm = Assembly()
    bodies: dict[str, Body] = {}

    def add_body(b: Body, dof_labels: tuple[str, ...], dof_mass: list[float]) -> None:
        if b.name in bodies:
            raise ConfigError(f"body name '{b.name}' is used twice")
        b.dofs = asm.add_dofs(b.name, dof_labels, dof_mass)
        bodies[b.name] = b

    def spring(name: str, kind: str, k: float, entries: dict[int, float], stage: str,
               body: str, planet: int = 0, label: str = "") -> None:
        asm.add_rank_one(Spring(name, kind, k, asm.row(entries), stage=stage, body=body,
                                planet=planet, bin=label))

    infos: dict[str, StageInfo] = {}
    for st in stages:
        pre = f"{st.name}." if st.prefix else ""
        roles: dict[str, str] = {}
        for role in CENTRAL:
            p = getattr(st, role)
            r = p["radius"]
            b = Body(pre + role, "central", p["mass"], p["inertia"], r, stage=st.name)
            add_body(b, ("x", "y", "u"), [p["mass"], p["mass"], p["inertia"] / r**2])
            roles[role] = b.name
        for n in range(st.n_planets):
            p = st.planet
            r = p["radius"]
            b = Body(f"{pre}planet{n + 1}", "planet", p["mass"], p["inertia"], r, stage=st.name)
            add_body(b, ("zeta", "eta", "u"), [p["mass"], p["mass"], p["inertia"] / r**2])
            roles[f"planet{n + 1}"] = b.name
        infos[st.name] = StageInfo(
            st.name,
            np.asarray(st.planet_angles, float),
            st.alpha_s,
            st.alpha_r,
            st.sun["radius"],
            st.ring["radius"],
            st.planet["radius"],
            st.carrier["radius"],
            st.z_sun,
            st.z_ring,
            st.z_planet,
            roles,
        )
    for r in rotors:
        add_body(Body(r.name, "rotor", r.inertia, r.inertia, 1.0), ("theta",), [r.inertia])

    for st in stages:
        info = infos[st.name]
        c, rg, s = (bodies[info.bodies[r]] for r in CENTRAL)
        for role, b in (("carrier", c), ("ring", rg), ("sun", s)):
            p = getattr(st, role)
            kb = p.get("bearing", 0.0)
            for j, d in enumerate(("x", "y")):
                spring(f"{b.name}.bearing.{d}", "bearing", kb, {b.dofs[j]: 1.0}, st.name,
                       b.name, label=f"bearing of {b.name} ({d})")
            kt = p.get("torsional", 0.0)
            spring(f"{b.name}.bearing.u", "support_u", kt / b.radius**2, {b.dofs[2]: 1.0},
                   st.name, b.name, label=f"bearing of {b.name} (rotation)")
        planets = [bodies[info.bodies[f"planet{i + 1}"]] for i in range(st.n_planets)]
        xc, yc, uc = c.dofs
        for i, pb in enumerate(planets):
            zc, ze, _up = pb.dofs
            cp, sp = math.cos(st.planet_angles[i]), math.sin(st.planet_angles[i])
            spring(f"{pb.name}.bearing.zeta", "planet_bearing", st.planet_bearing,
                   {xc: cp, yc: sp, zc: -1.0}, st.name, pb.name, i + 1,
                   f"bearing of {pb.name} (radial)")
            spring(f"{pb.name}.bearing.eta", "planet_bearing", st.planet_bearing,
                   {xc: -sp, yc: cp, uc: 1.0, ze: -1.0}, st.name, pb.name, i + 1,
                   f"bearing of {pb.name} (tangential)")
        for i, pb in enumerate(planets):
            zc, ze, up = pb.dofs
            ps = st.planet_angles[i] - st.alpha_s
            spring(f"{pb.name}.mesh_sun", "mesh_sun", st.k_sun_mesh,
                   {s.dofs[0]: -math.sin(ps), s.dofs[1]: math.cos(ps), s.dofs[2]: 1.0,
                    zc: -math.sin(st.alpha_s), ze: -math.cos(st.alpha_s), up: 1.0},
                   st.name, pb.name, i + 1, f"mesh {s.name}-{pb.name}")
        for i, pb in enumerate(planets):
            zc, ze, up = pb.dofs
            pr = st.planet_angles[i] + st.alpha_r
            spring(f"{pb.name}.mesh_ring", "mesh_ring", st.k_ring_mesh,
                   {rg.dofs[0]: -math.sin(pr), rg.dofs[1]: math.cos(pr), rg.dofs[2]: 1.0,
                    zc: math.sin(st.alpha_r), ze: -math.cos(st.alpha_r), up: -1.0},
                   st.name, pb.name, i + 1, f"mesh {rg.name}-{pb.name}")
        # the stage's members are described in the carrier frame (Ω = θ̇_c = u̇_c / r_c)
        asm.add_frame(st.name, asm.row({uc: 1.0 / c.radius}))
        skew = np.array([[0.0, -2.0], [2.0, 0.0]])
        for b in [c, rg, s, *planets]:
            asm.add_block(f"{b.name}.frame", "rotating_frame", b.dofs[:2], frame=st.name,
                          G=b.mass * skew, K_omega=b.mass * np.eye(2))
    for r in rotors:
        b = bodies[r.name]
        spring(f"{r.name}.support", "support_u", r.support, {b.dofs[0]: 1.0}, "", r.name,
               label=f"support of {r.name}")
    for sh in shafts:
        ba = _lookup(bodies, sh.a, f"shaft '{sh.name}'.a")
        bb = _lookup(bodies, sh.b, f"shaft '{sh.name}'.b")
        if sh.torsional:
            spring(f"{sh.name}.torsion", "shaft", sh.torsional,
                   {ba.dofs[-1]: 1.0 / ba.radius, bb.dofs[-1]: -1.0 / bb.radius}, "", sh.name,
                   label=f"shaft {sh.name} (torsion)")
        if sh.flexural:
            if ba.kind != "central" or bb.kind != "central":
                raise ConfigError(
                    f"shaft '{sh.name}': flexural stiffness needs two central members "
                    f"(sun, ring or carrier); got '{ba.name}' ({ba.kind}) and "
                    f"'{bb.name}' ({bb.kind})"
                )
            for j, d in enumerate(("x", "y")):
                spring(f"{sh.name}.flex.{d}", "shaft", sh.flexural,
                       {ba.dofs[j]: 1.0, bb.dofs[j]: -1.0}, "", sh.name,
                       label=f"shaft {sh.name} ({d})")
    model = PlanetaryModel(bodies, infos, asm, reduction)
    if reduction != "none":
        model.T = reduction_matrix(model, reduction)
    return model


def _lookup(bodies: dict[str, Body], name: str, where: str) -> Body:
    if name not in bodies:
        raise ConfigError(
            f"{where}: unknown body '{name}' (bodies: {', '.join(bodies)})"
        )
    return bodies[name]


def reduction_matrix(model: PlanetaryModel, reduction: str) -> np.ndarray:
    """q_full = T q_red for ``torsional`` (seed 003 model B) or ``transverse`` models."""
    n = model.n_full
    cols: list[np.ndarray] = []
    if reduction == "torsional":
        carrier_of: dict[str, int] = {}
        for info in model.stages.values():
            carrier_of[info.name] = model.bodies[info.bodies["carrier"]].dofs[2]
        for b in model.bodies.values():
            u = b.dofs[-1]
            col = np.zeros(n)
            col[u] = 1.0
            if b.kind == "central" and b.name == model.stages[b.stage].bodies["carrier"]:
                # planets' tangential motion follows the carrier (rigid planet bearings)
                for p in model.bodies.values():
                    if p.kind == "planet" and p.stage == b.stage:
                        col[p.dofs[1]] = 1.0
            cols.append(col)
    elif reduction == "transverse":
        for b in model.bodies.values():
            if b.kind == "rotor":
                continue
            for j in (0, 1):
                col = np.zeros(n)
                col[b.dofs[j]] = 1.0
                cols.append(col)
    else:
        raise ConfigError(
            f"reduction '{reduction}' is not one of 'none', 'torsional', 'transverse'"
        )
    return np.array(cols).T
