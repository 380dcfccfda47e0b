"""Assembly of the FE transmission (seed 002 eqs 2-3): shafts of Timoshenko elements, rigid
wheels, bearings and gear meshes as connecting forces; modal analysis and modal damping.

Global DOFs: 6 per node (x, y, z, θx, θy, θz), shafts numbered in config order, nodes along
+z from each shaft start. SI units. The linear part is built on the one assembly core
(:class:`geardyn.models.core.assembly.Assembly`): every node registers its DOFs as
``{shaft}.n{i}.{x,y,z,rx,ry,rz}`` (the order of :mod:`geardyn.elements.beam`), every Timoshenko
element and every wheel disc is a block whose kind is its shaft's name, so the per-shaft
gyroscopic matrix is ``assembly.matrix("G", kinds=[shaft])``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from geardyn.bearings.hertz import ball_race_stiffness, reduced_modulus, roller_race_stiffness
from geardyn.elements.beam import ShaftSection, timoshenko_element, timoshenko_gyroscopic
from geardyn.elements.disc import disc_gyroscopic, rigid_disc, solid_disc_properties
from geardyn.errors import ConfigError, InputError
from geardyn.gears.contact import johnson_modulus
from geardyn.models.core.assembly import Assembly
from geardyn.models.transmission.kernels import mesh_work_size

#: DOF labels of an FE shaft node, in the order of :func:`geardyn.elements.beam.timoshenko_element`
#: (translations x, y, z then rotations θx, θy, θz; m and rad).
NODE_DOFS = ("x", "y", "z", "rx", "ry", "rz")


def node_dofs(shaft: str, local: int) -> list[str]:
    """Names of the 6 DOFs of node ``local`` of ``shaft`` (``output.n3.ry``)."""
    return [f"{shaft}.n{local}.{d}" for d in NODE_DOFS]


@dataclass
class Bearings:
    """Structure-of-arrays bearing parameters (see :func:`.kernels.bearing_forces`)."""

    names: list[str]
    node: np.ndarray
    kind: np.ndarray  # 0 ball, 1 roller
    z: np.ndarray
    k: np.ndarray
    a0: np.ndarray
    pd: np.ndarray
    cage: np.ndarray
    dm: np.ndarray
    crr: np.ndarray
    visc: np.ndarray
    kax: np.ndarray
    cax: np.ndarray
    sp_ang: np.ndarray
    sp_len: np.ndarray
    sp_depth: np.ndarray

    def args(self) -> tuple:
        return (
            self.node, self.kind, self.z, self.k, self.a0, self.pd, self.cage, self.dm,
            self.crr, self.visc, self.kax, self.cax, self.sp_ang, self.sp_len, self.sp_depth,
            *pitch_rotation(self.z),
        )


def pitch_rotation(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(cos, sin) of the angular pitch 2π/Z of every bearing (the kernel's rolling-element
    angle recurrence; libm values, as the kernel's own math.cos would give)."""
    return (np.array([math.cos(2.0 * math.pi / int(n)) for n in z]),
            np.array([math.sin(2.0 * math.pi / int(n)) for n in z]))


@dataclass
class Meshes:
    """Structure-of-arrays gear-mesh parameters (see :func:`.kernels.mesh_forces`)."""

    names: list[str]
    na: np.ndarray
    nb: np.ndarray
    V: np.ndarray
    nsl: np.ndarray
    tlen: np.ndarray
    npc: np.ndarray
    za: np.ndarray
    s: np.ndarray
    xi0: np.ndarray
    ks: np.ndarray
    length: np.ndarray
    rsum: np.ndarray
    rhoa: np.ndarray
    rhob: np.ndarray
    npair: np.ndarray
    that: np.ndarray
    mu: np.ndarray
    csf: np.ndarray
    estar: np.ndarray
    gap: np.ndarray
    Vb: np.ndarray
    """Back-flank slice vectors (mirrored line of action)."""
    backlash: np.ndarray
    """Normal backlash j_bn [m] per mesh; < 0: drive flank only."""
    geometry: list = field(default_factory=list)
    tables: list = field(default_factory=list)

    def args(self) -> tuple:
        return (
            self.na, self.nb, self.V, self.nsl, self.tlen, self.npc, self.za, self.s,
            self.xi0, self.ks, self.length, self.rsum, self.rhoa, self.rhob, self.npair,
            self.that, self.mu, self.csf, self.estar, self.gap, self.Vb, self.backlash,
            np.empty(mesh_work_size(self.ks.shape[2], self.V.shape[1])),  # kernel scratch
        )


@dataclass
class SupportPart:
    """A linear support of the model: global DOFs (x, y, θx, θy) of its node and its 4×4
    stiffness and damping at the run's speed (force on the housing K u + C u̇)."""

    name: str
    node: int
    K: np.ndarray
    C: np.ndarray
    kzz: float = 0.0
    """Axial stiffness [N/m]."""
    table: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    """Speed table: (speeds rpm, K(n_i) − K, C(n_i) − C) for a speed that varies in the run;
    K, C are the values at the run's start speed (in the model's K and C_lin)."""

    @property
    def dofs(self) -> np.ndarray:
        return 6 * self.node + np.array([0, 1, 3, 4])


@dataclass
class TransmissionModel:
    """Assembled model: matrices (SI), connecting-force parameters, node bookkeeping."""

    M: np.ndarray
    K: np.ndarray
    node_xyz: np.ndarray
    shaft_nodes: dict[str, list[int]]
    shaft_sign: dict[str, float]
    bearings: Bearings
    meshes: Meshes
    drive_node: int
    load_node: int
    drive_torque: float
    load_torque: float
    modal_damping: float
    C: np.ndarray | None = None
    gyroscopic: dict[str, np.ndarray] = field(default_factory=dict)
    """Per shaft: gyroscopic matrix (shaft elements + its wheels) per rad/s of that shaft."""
    assembly: Assembly | None = None
    """The linear elements on the assembly core (Timoshenko elements, wheel discs)."""
    C_lin: np.ndarray | None = None
    """Damping of the linear supports and dashpots [N·s/m…] (None: none), added to the
    modal damping."""
    supports: list[SupportPart] = field(default_factory=list)
    discs: dict[str, int] = field(default_factory=dict)
    """Plain disc name → global node."""

    @property
    def dof_names(self) -> list[str]:
        """Name of every DOF (``{shaft}.n{i}.{x,y,z,rx,ry,rz}``), in the order of M and K."""
        if self.assembly is not None:
            return list(self.assembly.names)
        node_shaft = {nd: (s, j) for s, ids in self.shaft_nodes.items()
                      for j, nd in enumerate(ids)}
        return [f"{node_shaft[i // 6][0]}.n{node_shaft[i // 6][1]}.{NODE_DOFS[i % 6]}"
                for i in range(self.ndof)]

    def dof(self, shaft: str, local: int, label: str) -> int:
        """Global index of DOF ``label`` (one of x, y, z, rx, ry, rz) of a shaft node."""
        if label not in NODE_DOFS:
            raise InputError(f"DOF label must be one of {', '.join(NODE_DOFS)}, got {label!r}")
        if shaft not in self.shaft_nodes:
            raise InputError(f"unknown shaft '{shaft}' (one of {', '.join(self.shaft_nodes)})")
        ids = self.shaft_nodes[shaft]
        if not 0 <= local < len(ids):
            raise InputError(f"shaft '{shaft}' has nodes 0..{len(ids) - 1}, got {local}")
        return 6 * ids[local] + NODE_DOFS.index(label)

    @property
    def ndof(self) -> int:
        return self.M.shape[0]

    def node_of(self, shaft: str, local: int) -> int:
        return self.shaft_nodes[shaft][local]

    def node_sign(self, node: int) -> float:
        """Rotation sign (+1 CCW) of the shaft carrying ``node`` for a positive drive."""
        for name, ids in self.shaft_nodes.items():
            if node in ids:
                return self.shaft_sign[name]
        raise InputError(f"node {node} is on no shaft")


def assemble_shaft(section: ShaftSection, length: float, elements: int) -> tuple[np.ndarray, ...]:
    """(K, M) of a uniform shaft of ``elements`` equal Timoshenko elements."""
    n = elements + 1
    K = np.zeros((6 * n, 6 * n))
    M = np.zeros_like(K)
    ke, me = timoshenko_element(length / elements, section)
    for e in range(elements):
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += ke
        M[sl, sl] += me
    return K, M


def modal_analysis(
    M: np.ndarray, K: np.ndarray, fixed: list[int] | np.ndarray = ()
) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (Hz, ascending) and mass-normalised mode shapes (full DOF size,
    zeros on ``fixed`` DOFs) of the undamped system (gyroscopic terms neglected);
    :func:`geardyn.solve.eigen.eigenmodes` without rigid-mode snapping."""
    from geardyn.solve.eigen import eigenmodes

    em = eigenmodes(M, K, fixed, zero_hz=0.0)
    return em.freq_hz, em.shapes


def modal_damping_matrix(M: np.ndarray, K: np.ndarray, zeta: float) -> np.ndarray:
    """C = M Φ diag(2 ζ ω_i) Φᵀ M (seed 002 §2.1, modal ratio ζ); rigid modes undamped."""
    f, phi = modal_analysis(M, K)
    w = 2 * math.pi * f
    w[f < 0.5] = 0.0  # rigid-body modes (drive-line rotation) carry no modal damping
    mp = M @ phi
    return (mp * (2 * zeta * w)) @ mp.T


def _rotation_signs(t, pair_shafts: dict[str, tuple[str, str]]) -> dict[str, float]:
    """Rotation sign of each shaft (+1 = CCW about +z) for a positive drive rotation."""
    sign = {t.drive.at.shaft: 1.0}
    changed = True
    while changed:
        changed = False
        for sa, sb in pair_shafts.values():
            if sa in sign and sb not in sign:
                sign[sb] = -sign[sa]
                changed = True
            elif sb in sign and sa not in sign:
                sign[sa] = -sign[sb]
                changed = True
    for s in t.shafts:
        sign.setdefault(s.name, 1.0)
    return sign


def _driver_order(t, pair_shafts) -> dict[str, int]:
    """Distance (in meshes) of each shaft from the drive shaft."""
    dist = {t.drive.at.shaft: 0}
    for _ in range(len(pair_shafts) + 1):
        for sa, sb in pair_shafts.values():
            if sa in dist and sb not in dist:
                dist[sb] = dist[sa] + 1
            if sb in dist and sa not in dist:
                dist[sa] = dist[sb] + 1
    return dist


def build_model(cfg, mesh_points_per_cycle: int | None = None) -> TransmissionModel:  # noqa: ANN001
    """Assemble the transmission of a loaded :class:`~geardyn.config.GeardynConfig`."""
    from geardyn.gears.pe_stiffness import mesh_stiffness
    from geardyn.models.gear_pairs import pair_model

    t = cfg.transmission
    if t is None:
        raise ConfigError("transmission: section missing (nothing to simulate)")
    # --- shafts: 6 named DOFs per node, one Timoshenko block per element (kind = shaft name)
    asm = Assembly()
    shaft_nodes: dict[str, list[int]] = {}
    xyz = []
    n0 = 0
    for s in t.shafts:
        ids = list(range(n0, n0 + s.elements + 1))
        shaft_nodes[s.name] = ids
        for i in range(s.elements + 1):
            asm.add_dofs(f"{s.name}.n{i}", NODE_DOFS)
            xyz.append((s.position_m[0], s.position_m[1], s.length_m * i / s.elements))
        n0 += s.elements + 1
    for s in t.shafts:
        sec = ShaftSection(
            s.outer_diameter_m, s.inner_diameter_m, s.youngs_modulus_pa, s.poisson_ratio,
            s.density_kg_m3,
        )
        ke, me = timoshenko_element(s.length_m / s.elements, sec, t.mass)
        ge = timoshenko_gyroscopic(s.length_m / s.elements, sec)
        for e in range(s.elements):
            dofs = node_dofs(s.name, e) + node_dofs(s.name, e + 1)
            asm.add_block(f"{s.name}.e{e}", s.name, dofs, K=ke, M=me, G=ge)
    node_xyz = np.array(xyz)

    def node(ref) -> int:  # noqa: ANN001
        return shaft_nodes[ref.shaft][ref.node]

    # --- wheels (rigid discs between bore and pitch radius; M and G blocks on their node)
    pairs = {m.pair: pair_model(cfg, m.pair) for m in t.meshes}
    for w in t.wheels:
        pm = pairs.get(w.pair) or pair_model(cfg, w.pair)
        g = pm.geometry
        side = 0 if w.gear == "a" else 1
        blank = (g.a, g.b)[side]
        r_in = blank.rim_radius or 0.0
        mass, ip, idia = solid_disc_properties(
            g.pitch_radius[side], r_in, g.face_width, blank.material.density
        )
        asm.add_block(f"wheel.{w.pair}.{w.gear}", w.at.shaft, node_dofs(w.at.shaft, w.at.node),
                      M=rigid_disc(mass, ip, idia), G=disc_gyroscopic(ip))
    # --- plain discs (rigid, centre of mass ``offset_m`` along z from the node: x_cm =
    # x + e θy, y_cm = y − e θx with θy = dx/dz, θx = −dy/dz; M = Tᵀ M_cm T)
    for d in t.discs:
        mass, ip, idia = d.properties()
        T = np.eye(6)
        T[0, 4], T[1, 3] = d.offset_m, -d.offset_m
        asm.add_block(f"disc.{d.name}", d.at.shaft, node_dofs(d.at.shaft, d.at.node),
                      M=T.T @ rigid_disc(mass, ip, idia) @ T, G=disc_gyroscopic(ip))
    K = asm.matrix("K")
    M = asm.matrix("M")
    gyro = {s.name: asm.matrix("G", kinds=[s.name]) for s in t.shafts}
    # --- bearings
    nb = len(t.bearings)
    B = Bearings(
        names=[b.name for b in t.bearings],
        node=np.array([node(b.at) for b in t.bearings], dtype=np.int64),
        kind=np.array([0 if b.kind == "ball" else 1 for b in t.bearings], dtype=np.int64),
        z=np.array([b.elements for b in t.bearings], dtype=np.int64),
        k=np.zeros(nb), a0=np.zeros(nb),
        pd=np.array([b.diametral_clearance_m for b in t.bearings], dtype=float),
        cage=np.zeros(nb), dm=np.array([b.pitch_diameter_m for b in t.bearings], dtype=float),
        crr=np.array([b.rolling_resistance for b in t.bearings], dtype=float),
        visc=np.array([b.viscous_torque_nms_per_rad for b in t.bearings], dtype=float),
        kax=np.array([b.flange_stiffness_n_per_m for b in t.bearings], dtype=float),
        cax=np.array([b.axial_clearance_m for b in t.bearings], dtype=float),
        sp_ang=np.zeros(nb), sp_len=np.zeros(nb), sp_depth=np.zeros(nb),
    )
    for i, b in enumerate(t.bearings):
        ep = reduced_modulus(b.youngs_modulus_pa, b.poisson_ratio, b.youngs_modulus_pa,
                             b.poisson_ratio)
        B.cage[i] = 0.5 * (1.0 - b.element_diameter_m / b.pitch_diameter_m)
        if b.kind == "ball":
            B.k[i] = ball_race_stiffness(
                b.element_diameter_m, b.pitch_diameter_m, b.inner_conformity,
                b.outer_conformity, ep,
            )[2]
            B.a0[i] = (b.inner_conformity + b.outer_conformity - 1.0) * b.element_diameter_m
        else:
            B.k[i] = roller_race_stiffness(b.roller_length_m - 2 * b.roller_fillet_m)
        if b.outer_spall is not None:
            B.sp_ang[i] = math.radians(b.outer_spall.angle_deg)
            B.sp_len[i] = math.radians(b.outer_spall.angular_length_deg)
            B.sp_depth[i] = b.outer_spall.depth_m
    # --- meshes
    wheel_at = {(w.pair, w.gear): w.at for w in t.wheels}
    pair_shafts = {m.pair: (wheel_at[(m.pair, "a")].shaft, wheel_at[(m.pair, "b")].shaft)
                   for m in t.meshes}
    sign = _rotation_signs(t, pair_shafts)
    order = _driver_order(t, pair_shafts)
    nm = len(t.meshes)
    tabs, geoms = [], []
    for i, mc in enumerate(t.meshes):
        sa, sb = pair_shafts[mc.pair]
        if order.get(sa, 0) > order.get(sb, 0):
            raise ConfigError(
                f"transmission.meshes[{i}].pair: gear a of '{mc.pair}' must be the driving "
                "gear (on the drive side of the mesh)"
            )
        pm = pairs[mc.pair]
        npc = mesh_points_per_cycle or mc.table_points_per_cycle
        tabs.append(mesh_stiffness(pm.geometry, n_per_cycle=npc,
                                   n_cycles=None if pm.faults else 1.0, faults=pm.faults))
        geoms.append(pm.geometry)
    nmax = max((tb.total.size for tb in tabs), default=1)
    pmax = max((tb.pair_stiffness.shape[1] + 2 for tb in tabs), default=1)
    smax = max((mc.slices for mc in t.meshes), default=1)
    Mh = Meshes(
        names=[m.pair for m in t.meshes],
        na=np.zeros(nm, np.int64), nb=np.zeros(nm, np.int64), V=np.zeros((nm, smax, 12)),
        nsl=np.array([m.slices for m in t.meshes], np.int64),
        tlen=np.zeros(nm, np.int64), npc=np.zeros(nm), za=np.zeros(nm), s=np.zeros(nm),
        xi0=np.zeros(nm), ks=np.zeros((nm, nmax, pmax)), length=np.zeros((nm, nmax, pmax)),
        rsum=np.ones((nm, nmax, pmax)), rhoa=np.zeros((nm, nmax, pmax)),
        rhob=np.zeros((nm, nmax, pmax)), npair=np.zeros(nm, np.int64), that=np.zeros((nm, 3)),
        mu=np.array([m.friction_coefficient for m in t.meshes], float),
        csf=np.array([m.squeeze_film_ns_per_m for m in t.meshes], float),
        estar=np.zeros(nm), gap=np.zeros((nm, nmax, pmax)), Vb=np.zeros((nm, smax, 12)),
        backlash=np.array([-1.0 if m.backlash_m is None else m.backlash_m for m in t.meshes],
                          float),
        geometry=geoms, tables=tabs,
    )
    for i, mc in enumerate(t.meshes):
        g, tb = geoms[i], tabs[i]
        ia, ib = node(wheel_at[(mc.pair, "a")]), node(wheel_at[(mc.pair, "b")])
        Mh.na[i], Mh.nb[i] = ia, ib
        s = sign[pair_shafts[mc.pair][0]]
        Mh.s[i] = s
        Mh.za[i] = g.a.teeth
        n = tb.total.size
        Mh.tlen[i] = n
        Mh.npc[i] = tb.n_per_cycle
        ks, length, u, gap = _pair_tables(g, tb, pairs[mc.pair].corrections,
                                          mc.off_line_of_action)
        npair = ks.shape[1]
        Mh.npair[i] = npair
        Mh.gap[i, :n, :npair] = gap
        Mh.ks[i, :n, :npair] = ks
        Mh.length[i, :n, :npair] = length
        tw = math.tan(g.working_pressure_angle)
        Mh.rhoa[i, :n, :npair] = g.base_radius[0] * tw + u
        Mh.rhob[i, :n, :npair] = g.base_radius[1] * tw - u
        Mh.rsum[i, :n, :npair] = Mh.rhoa[i, :n, :npair] + Mh.rhob[i, :n, :npair]
        ma = g.a.material
        Mh.estar[i] = johnson_modulus(ma.youngs_modulus, ma.poisson_ratio)
        # geometry: e from O_a to O_b, transverse LOA normal n, tangent t = z × n
        pa, pb = node_xyz[ia], node_xyz[ib]
        e = np.array([pb[0] - pa[0], pb[1] - pa[1], 0.0])
        e /= np.linalg.norm(e)
        eperp = np.array([-e[1], e[0], 0.0])
        al = g.working_pressure_angle
        nvec = math.sin(al) * e + s * math.cos(al) * eperp
        that = np.cross([0.0, 0.0, 1.0], nvec)
        Mh.that[i] = that
        rho0 = g.base_radius[0] * math.tan(al)
        zk = (np.arange(mc.slices) + 0.5) / mc.slices * g.face_width - 0.5 * g.face_width
        # drive flank (sense s), back flank: the mirrored line of action (sense −s)
        for V, sf in ((Mh.V, s), (Mh.Vb, -s)):
            nvec = math.sin(al) * e + sf * math.cos(al) * eperp
            that = np.cross([0.0, 0.0, 1.0], nvec)
            hand = sf * math.copysign(1.0, g.helix_angle) if g.helix_angle != 0 else 0.0
            n3 = nvec + np.array([0.0, 0.0, hand * math.tan(abs(g.base_helix_angle))])
            for k in range(mc.slices):
                p_a = -sf * g.base_radius[0] * that + rho0 * nvec + np.array([0.0, 0.0, zk[k]])
                p_b = p_a + (pa - pb) * np.array([1.0, 1.0, 0.0])
                p_b[2] = zk[k]
                V[i, k, :3] = n3
                V[i, k, 3:6] = np.cross(p_a, n3)
                V[i, k, 6:9] = -n3
                V[i, k, 9:12] = -np.cross(p_b, n3)
    drive_node, load_node = node(t.drive.at), node(t.load.at)
    # --- linear supports and dashpots: constant matrices added to K and to C_lin
    supports, C_lin = _linear_parts(t, K, node, shaft_nodes, Mh)
    return TransmissionModel(
        M=M, K=K, node_xyz=node_xyz, shaft_nodes=shaft_nodes, shaft_sign=sign, bearings=B,
        meshes=Mh, drive_node=drive_node, load_node=load_node,
        drive_torque=t.drive.torque_nm, load_torque=t.load.torque_nm,
        modal_damping=t.modal_damping, gyroscopic=gyro, assembly=asm, C_lin=C_lin,
        supports=supports, discs={d.name: node(d.at) for d in t.discs},
    )


def _linear_parts(t, K: np.ndarray, node, shaft_nodes: dict[str, list[int]],  # noqa: ANN001
                  meshes: Meshes) -> tuple[list[SupportPart], np.ndarray | None]:
    """Stamp the linear supports (4×4 on x, y, θx, θy; axial kzz, czz) and dashpots into K
    (in place) and a damping matrix; speed-tabulated coefficients are evaluated at the run's
    start speed (``speed_law.start_rpm`` of its reference, or ``simulation.initial_rpm`` of
    the drive shaft, times the shaft's speed ratio) and their table kept for the loops, which
    follow the current speed (:func:`geardyn.solve.explicit.applied_loads`)."""
    from types import SimpleNamespace

    if not t.supports and not t.dashpots:
        return [], None
    n = K.shape[0]
    C = np.zeros((n, n))
    ref_shaft = t.drive.at.shaft
    if t.speed_law is not None:
        ref_shaft = t.speed_law.reference.shaft
        ref_rpm = t.speed_law.start_rpm
    else:
        ref_rpm = t.simulation.initial_rpm or 0.0
    from geardyn.models.transmission.simulate import speed_ratios

    ratios = speed_ratios(SimpleNamespace(meshes=meshes, shaft_nodes=shaft_nodes), ref_shaft)
    parts = []
    for sc in t.supports:
        rpm = ref_rpm * ratios.get(sc.at.shaft, 0.0)
        k4, c4 = (np.array(m, float) for m in sc.matrices(rpm))
        nd = node(sc.at)
        part = SupportPart(sc.name, nd, k4, c4, sc.kzz_n_per_m)
        if sc.speeds_rpm is not None:
            tab = [tuple(np.array(m, float) for m in sc.matrices(r)) for r in sc.speeds_rpm]
            part.table = (np.array(sc.speeds_rpm, float),
                          np.array([k for k, _ in tab]) - k4, np.array([c for _, c in tab]) - c4)
        ix = np.ix_(part.dofs, part.dofs)
        K[ix] += k4
        C[ix] += c4
        K[6 * nd + 2, 6 * nd + 2] += sc.kzz_n_per_m
        C[6 * nd + 2, 6 * nd + 2] += sc.czz_ns_per_m
        parts.append(part)
    for d in t.dashpots:
        j = 6 * node(d.at) + NODE_DOFS.index(d.dof)
        idx = [j] if d.to is None else [j, 6 * node(d.to) + NODE_DOFS.index(d.dof)]
        e = np.array([1.0, -1.0][: len(idx)])
        K[np.ix_(idx, idx)] += d.stiffness * np.outer(e, e)
        C[np.ix_(idx, idx)] += d.damping * np.outer(e, e)
    return parts, C


def _pair_tables(g, tb, corrections=None, extended: bool = True):  # noqa: ANN001, ANN202
    """Per table sample and tooth pair (columns = pair age −1 … P relative to floor(ξ)):
    structural stiffness K_tot (N/m, the table's pair stiffness without the constant Hertz
    compliance it contains), loaded face width L (m), LOA position u (m) and the no-load gap
    (m): separation distance D of off-line-of-action contact (seed 002 eq 11, spur pairs,
    up to 0.4 p_bt outside the path as in :func:`geardyn.gears.static_transmission_error`)
    plus profile corrections δ_corr at mid-face (eq 12).

    Off the path the stiffness is that of the path end (healthy), as in the loaded module."""
    from geardyn.gears.contact import hertz_compliance
    from geardyn.gears.loaded import correction, separation_distance
    from geardyn.gears.pe_stiffness import pair_compliance_curve

    ma, mb = g.a.material, g.b.material
    ch = hertz_compliance(ma.youngs_modulus, ma.poisson_ratio, mb.youngs_modulus, mb.poisson_ratio)
    n, npair = tb.pair_stiffness.shape
    ncol = npair + 2
    xi = tb.mesh_cycle
    age = np.arange(-1, npair + 1)
    # nominal mid-face LOA position of every column (helical: the table's mid slice)
    lag = 0.5 * g.face_width * math.tan(abs(g.base_helix_angle))
    u = g.u_start + (xi - np.floor(xi))[:, None] * g.base_pitch + age[None, :] * g.base_pitch
    u = u - lag
    kp = np.zeros((n, ncol))
    kp[:, 1:-1] = tb.pair_stiffness
    ugrid = np.linspace(g.u_start, g.u_end, 401)
    kbar_grid = 1.0 / pair_compliance_curve(g, ugrid)  # per unit width
    uc = np.clip(u, g.u_start, g.u_end)
    kbar = np.interp(uc, ugrid, kbar_grid)
    gap = np.zeros((n, ncol))
    ext = 0.4 * g.base_pitch if (extended and g.helix_angle == 0.0 and not g.internal) else 0.0
    if ext > 0:
        off = ((u < g.u_start) & (u >= g.u_start - ext)) | ((u > g.u_end) & (u <= g.u_end + ext))
        kp = np.where(off & (kp == 0.0), kbar * g.face_width, kp)
        gap = np.where(off, separation_distance(g, u.ravel()).reshape(u.shape), 0.0)
    if corrections is not None:
        gap = gap + correction(g, corrections, u, np.full_like(u, 0.5 * g.face_width))
    length = np.where(kp > 0, np.minimum(kp / kbar, g.face_width), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ks = np.where(kp > 0, 1.0 / (1.0 / kp - ch / np.maximum(length, 1e-12)), 0.0)
    ks = np.where(np.isfinite(ks) & (ks > 0), ks, 0.0)
    gap = np.where(ks > 0, gap, 0.0)
    return ks, length, uc, gap


def connecting_forces(model: TransmissionModel, q: np.ndarray, v: np.ndarray,
                      args: tuple | None = None) -> np.ndarray:
    """Bearing + mesh forces (N, N·m) on every DOF at state (q, v); ``args``: the kernels'
    (bearing, mesh) arguments when the caller already has them (repeated calls)."""
    from geardyn.models.transmission.kernels import bearing_forces, mesh_forces

    ba, ma = args or (model.bearings.args(), model.meshes.args())
    f = np.zeros(model.ndof)
    diss = np.zeros(5)
    bl = np.zeros((model.bearings.node.size, 3))
    mf = np.zeros(model.meshes.na.size)
    bearing_forces(q, v, f, diss, *ba, bl)
    mesh_forces(q, v, f, diss, *ma, mf)
    return f


def kernel_dofs(model: TransmissionModel) -> np.ndarray:
    """The global DOFs whose displacement the connecting forces read (sorted): x, y, z and θz
    of every bearing node (:func:`.kernels.bearing_forces`), all six DOFs of both nodes of
    every mesh (:func:`.kernels.mesh_forces`). The forces do not change when any other DOF
    moves, so a finite-difference column of another DOF is exactly zero."""
    dofs = {6 * int(nd) + k for nd in model.bearings.node for k in (0, 1, 2, 5)}
    for a, b in zip(model.meshes.na, model.meshes.nb, strict=True):
        dofs.update(6 * int(nd) + k for nd in (a, b) for k in range(6))
    return np.array(sorted(dofs), np.int64)


def perturbed_forces(model: TransmissionModel, q: np.ndarray, v: np.ndarray, cols: np.ndarray,
                     h: float, args: tuple | None = None) -> np.ndarray:
    """(ndof, cols.size): column k the connecting forces at q + h e_cols[k] (a
    finite-difference Jacobian's evaluations in one compiled call: the values of
    :func:`connecting_forces`, without a Python call per column)."""
    from geardyn.models.transmission.kernels import perturbed_connecting_forces

    ba, ma = args or (model.bearings.args(), model.meshes.args())
    out = np.zeros((q.size, cols.size))
    perturbed_connecting_forces(np.asarray(q, float), np.asarray(v, float),
                                np.asarray(cols, np.int64), float(h), ba, ma,
                                model.bearings.node.size, model.meshes.na.size, out)
    return out


def static_equilibrium(
    model: TransmissionModel, load_torque: float, q0: np.ndarray | None = None,
    tol: float = 1e-10, max_iter: int = 500,
) -> np.ndarray:
    """Static deflection under ``load_torque`` (N·m, resisting, at the load node) with the
    drive node's θz held (Newton with a finite-difference Jacobian; seed 002 eq 3 at rest).
    When Newton does not converge from ``q0`` (a bearing whose clearance closes under load can
    trap the limited steps at a contact kink), the load is applied in four steps, each solved
    from the previous deflection (load continuation); InputError when that fails too.

    The drive torque is the reaction at the held DOF."""
    q = _equilibrium_newton(model, load_torque, q0, tol, max_iter)
    if q is not None:
        return q
    q = q0
    for frac in (0.25, 0.5, 0.75, 1.0):
        q = _equilibrium_newton(model, frac * load_torque, q, tol, max_iter)
        if q is None:
            raise InputError(
                f"static equilibrium did not converge at {frac:.0%} of the load torque "
                f"{load_torque:g} N·m, also with the load applied in steps (check clearances "
                "and loads)")
    return q


def _equilibrium_newton(model: TransmissionModel, load_torque: float, q0: np.ndarray | None,
                        tol: float, max_iter: int) -> np.ndarray | None:
    """Newton iterations of :func:`static_equilibrium` (None when they do not converge)."""
    n = model.ndof
    held = 6 * model.drive_node + 5
    free = np.setdiff1d(np.arange(n), [held])
    fext = np.zeros(n)
    fext[6 * model.load_node + 5] = -model.node_sign(model.load_node) * load_torque
    q = np.zeros(n) if q0 is None else q0.copy()
    v = np.zeros(n)
    # weak ground springs (1 kN/m) on translations keep unloaded clearances solvable
    kreg = np.zeros(n)
    kreg[np.arange(n) % 6 < 3] = 1e3
    Kr = model.K + np.diag(kreg)
    args = (model.bearings.args(), model.meshes.args())

    def resid(qq: np.ndarray) -> np.ndarray:
        return (Kr @ qq - connecting_forces(model, qq, v, args) - fext)[free]

    # finite-difference columns of the DOFs the forces read (the others are exactly zero)
    cols = np.flatnonzero(np.isin(free, kernel_dofs(model)))
    for _ in range(max_iter):
        r = resid(q)
        J = Kr[np.ix_(free, free)].copy()
        h = 1e-9
        f0 = connecting_forces(model, q, v, args)
        F = perturbed_forces(model, q, v, free[cols], h, args)
        J[:, cols] -= (F[free] - f0[free, None]) / h
        dq = np.linalg.solve(J, -r)
        # limit the step (clearances make the first tangent nearly singular)
        trans = (free % 6) < 3
        big = np.abs(dq[trans]).max() if trans.any() else 0.0
        rot = np.abs(dq[~trans]).max() if (~trans).any() else 0.0
        alpha = min(1.0, 5e-6 / big if big > 0 else 1.0, 1e-4 / rot if rot > 0 else 1.0)
        if alpha == 1.0 and np.abs(dq).max() < tol:
            q[free] += dq
            return q
        # backtracking on the residual norm (contact entry/exit kinks)
        # (when no shorter step lowers the residual, e.g. across a clearance, take the
        # limited step)
        r0 = np.linalg.norm(r)
        step = alpha
        for _ in range(12):
            qt = q.copy()
            qt[free] += step * dq
            if np.linalg.norm(resid(qt)) < r0:
                break
            step *= 0.5
        else:
            qt = q.copy()
            qt[free] += alpha * dq
        q = qt
    return None


def mesh_state(
    model: TransmissionModel, q: np.ndarray, v: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(normal force N, mean slice deflection m, mesh phase ξ) of every mesh at state q."""
    from geardyn.models.transmission.kernels import mesh_forces

    mh = model.meshes
    v = np.zeros_like(q) if v is None else v
    f = np.zeros(model.ndof)
    diss = np.zeros(5)
    mf = np.zeros(mh.na.size)
    mesh_forces(q, v, f, diss, *mh.args(), mf)
    defl = np.zeros(mh.na.size)
    xi = np.zeros(mh.na.size)
    for i in range(mh.na.size):
        qa = q[6 * mh.na[i] : 6 * mh.na[i] + 6]
        qb = q[6 * mh.nb[i] : 6 * mh.nb[i] + 6]
        d = mh.V[i, : mh.nsl[i], :6] @ qa + mh.V[i, : mh.nsl[i], 6:] @ qb
        defl[i] = d.mean()
        xi[i] = mh.za[i] * mh.s[i] * qa[5] / (2 * math.pi) + mh.xi0[i]
    return mf, defl, xi


def rigid_rotation(model: TransmissionModel, ratios: dict[str, float], angle: float) -> np.ndarray:
    """DOF vector of the kinematic rigid rotation: reference shaft turned by ``angle`` (rad)."""
    q = np.zeros(model.ndof)
    for s, ids in model.shaft_nodes.items():
        for nd in ids:
            q[6 * nd + 5] = model.shaft_sign[s] * ratios[s] * angle
    return q


def campbell(
    model: TransmissionModel,
    K_lin: np.ndarray,
    speeds_rpm: np.ndarray,
    ratios: dict[str, float],
    n_modes: int = 20,
    track: bool = False,
):  # noqa: ANN201 - xarray.DataArray
    """Campbell diagram: undamped whirl frequencies (Hz) of M q̈ + G(Ω) q̇ + K_lin q = 0 at the
    reference-shaft speeds ``speeds_rpm``, each shaft spinning at ``ratios[shaft]`` × the
    reference speed in its own direction (gyroscopic terms of shafts and wheels;
    :func:`geardyn.solve.eigen.campbell`).

    Returns a DataArray (speed_rpm, mode) of the lowest ``n_modes`` frequencies above 0.5 Hz
    (the drive line's rigid-body rotation left out), sorted, or followed mode by mode along the
    speeds with ``track``."""
    import xarray as xr

    from geardyn.solve.eigen import campbell as eigen_campbell

    rpm = np.asarray(speeds_rpm, dtype=float)
    terms = [(model.shaft_sign[s] * ratios[s], g, None) for s, g in model.gyroscopic.items()]
    out = eigen_campbell(model.M, K_lin, terms, rpm * math.pi / 30.0, n_modes, min_hz=0.5,
                         track=track)
    return xr.DataArray(
        out, dims=("speed_rpm", "mode"),
        coords={"speed_rpm": rpm, "mode": np.arange(n_modes)},
        name="frequency_hz", attrs={"units": "Hz"},
    )
