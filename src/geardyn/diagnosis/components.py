"""Machine components for diagnosis, from the kinematics (seed 000).

For a 1-DOF mechanism every link turns at a fixed ratio of a reference link (seed 000 eq 5,
``Ω = Ω0 Λ``): ``ω_link = r_link·ω_ref``. This module turns that ratio table into the list of
components whose faults a diagnosis looks for, each with

* its **own angle** ``θ_own = r_own·θ_ref`` [rad] — the angle in which its fault is periodic:
  a shaft's own rotation; a wheel's rotation relative to the carrier of its meshes
  (``θ_w − θ_c``: a sun relative to its carrier, a planet relative to its carrier, a ring
  relative to the carrier — for a fixed ring, minus the carrier angle). Ratios are **signed**
  (a counter-rotating shaft has ``r < 0``); angle-domain processing uses ``|r|·θ_ref`` so that a
  negative ratio never reverses the resampling grid;
* its **mesh orders** in that angle: the tooth count of a wheel, the tooth counts of every wheel
  of a shaft whose meshes are periodic in the shaft angle (fixed-axis meshes), ``Z_s``, ``Z_p``
  and ``Z_r`` for sun, planet and ring (mesh frequency ``Z·|ω_w − ω_c|/2π``, seed 000 eq 2);
* for bearings, the fault orders BPFO/BPFI/BSF/FTF of the reference (kinematics ``bearings``
  table: Harris' formulas with the speeds of the two rings).

Spatial (bevel) links have complex ratios; their magnitude is used and their sign is that of
the real part (their rotation is about another axis, so a sign relative to the reference is a
convention).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from geardyn.errors import InputError
from geardyn.kinematics import KinematicAnalysis, MechanismGraph, analyze_kinematics

if TYPE_CHECKING:
    from geardyn.config import Mechanism

#: Bearing fault lines, as named in the kinematics bearings table (``<line>_order``).
BEARING_LINES = ("BPFO", "BPFI", "BSF", "FTF")
#: Component kinds, as used in the features table.
KINDS = ("shaft", "wheel", "bearing", "sun", "planet", "ring")


@dataclass(frozen=True)
class Component:
    """One diagnosable component.

    ``name``: component name (link, wheel or bearing name); ``kind``: one of :data:`KINDS`;
    ``link``: the link it sits on; ``ratio``: signed own-angle ratio ``θ_own/θ_ref``;
    ``mesh_orders``: mesh orders (tooth counts) periodic in the own angle, own wheel first;
    ``other_orders``: tooth counts of the other wheels sharing the own-angle domain (same link
    and carrier) — their mesh harmonics and nearby sidebands are ambiguous for this wheel;
    ``teeth``: tooth count (wheels); ``fault_orders``: bearing lines as orders of the reference
    (bearings; keys :data:`BEARING_LINES`); ``stage``/``planet``: the planetary stage and the
    planet index (planets, 0-based) a component belongs to.
    """

    name: str
    kind: str
    link: str
    ratio: float
    mesh_orders: tuple[int, ...] = ()
    other_orders: tuple[int, ...] = ()
    teeth: int | None = None
    others: tuple[str, ...] = ()
    carrier: str = ""
    fault_orders: Mapping[str, float] = field(default_factory=dict)
    stage: str | None = None
    planet: int | None = None

    @property
    def abs_ratio(self) -> float:
        """``|ratio|``: own revolutions per reference revolution (angle processing uses it)."""
        return abs(self.ratio)


@dataclass(frozen=True)
class PlanetaryStageInfo:
    """A planetary stage as a diagnosis sees it (seed 003 §4.1, seed 004 §8.2).

    Links ``sun``, ``ring``, ``carrier``, ``planets``; tooth counts; ``planet_angles`` [rad];
    signed ratios to the reference: ``carrier_ratio`` (absolute carrier), ``sun_ratio``,
    ``planet_ratio`` and ``ring_ratio`` relative to the carrier (``θ_x − θ_c``).
    ``ring_fixed``: the ring is the frame (a ring accelerometer then sees each planet pass).
    """

    name: str
    sun: str
    ring: str
    carrier: str
    planets: tuple[str, ...]
    sun_teeth: int
    ring_teeth: int
    planet_sun_teeth: int
    planet_ring_teeth: int
    planet_angles: tuple[float, ...]
    carrier_ratio: float
    sun_ratio: float
    planet_ratio: float
    ring_ratio: float
    ring_fixed: bool

    @property
    def n_planets(self) -> int:
        return len(self.planets)


@dataclass
class Components:
    """Every diagnosable component of a mechanism, referred to one reference link.

    ``ratios``: signed speed ratio ``ω_link/ω_ref`` of every link (frame 0);
    ``items``: the components (shafts, wheels — kinds wheel/sun/planet/ring — and bearings);
    ``planetary``: the planetary stages; ``analysis``: the kinematics they come from;
    ``input_speeds``: the operating point of a mechanism with more than one DOF (else None).
    """

    mechanism: str
    reference: str
    ratios: dict[str, float]
    items: list[Component]
    planetary: list[PlanetaryStageInfo]
    analysis: KinematicAnalysis | None = None
    input_speeds: dict[str, float] | None = None

    def of_kind(self, *kinds: str) -> list[Component]:
        """Components of the given kinds, in table order."""
        return [c for c in self.items if c.kind in kinds]

    @property
    def shafts(self) -> list[Component]:
        return self.of_kind("shaft")

    @property
    def wheels(self) -> list[Component]:
        """Toothed wheels of every kind (wheel, sun, planet, ring)."""
        return self.of_kind("wheel", "sun", "planet", "ring")

    @property
    def bearings(self) -> list[Component]:
        return self.of_kind("bearing")

    def __getitem__(self, name: str) -> Component:
        for c in self.items:
            if c.name == name:
                return c
        known = [c.name for c in self.items]
        raise InputError(f"component: unknown name {name!r} (known: {known})")

    def table(self) -> pd.DataFrame:
        """One row per component: name, kind, link, ratio (signed own-angle ratio), mesh
        orders, ambiguous (other wheels') orders, teeth and bearing orders of the reference."""
        rows = []
        for c in self.items:
            row = {
                "component": c.name,
                "kind": c.kind,
                "link": c.link,
                "ratio": c.ratio,
                "mesh_orders": ", ".join(str(o) for o in c.mesh_orders),
                "other_orders": ", ".join(str(o) for o in c.other_orders),
                "teeth": c.teeth,
            }
            for line in BEARING_LINES:
                row[f"{line.lower()}_order"] = c.fault_orders.get(line, np.nan)
            rows.append(row)
        return pd.DataFrame(rows)


def _as_analysis(cfg: Mechanism | MechanismGraph | KinematicAnalysis) -> KinematicAnalysis:
    if isinstance(cfg, KinematicAnalysis):
        return cfg
    if isinstance(cfg, MechanismGraph) or hasattr(cfg, "graph"):
        return analyze_kinematics(cfg)
    raise InputError(
        f"cfg: expected a Mechanism/GeardynConfig, MechanismGraph or KinematicAnalysis, "
        f"got {type(cfg).__name__}"
    )


def _real_ratio(z: complex) -> float:
    """Signed real ratio of a (possibly spatial) link: real part for planar links, else the
    magnitude with the sign of the real part."""
    z = complex(z)
    if abs(z.imag) <= 1e-9 * max(abs(z), 1.0):
        return float(z.real)
    return float(np.copysign(abs(z), z.real if z.real != 0 else 1.0))


def link_ratios(
    analysis: KinematicAnalysis,
    reference: str,
    input_speeds: Mapping[str, float] | None = None,
) -> dict[str, float]:
    """Signed ratios ``ω_link/ω_reference`` of every link (seed 000 eq 5), real (see
    :func:`complex_link_ratios` for spatial mechanisms)."""
    return {
        k: _real_ratio(v) for k, v in complex_link_ratios(analysis, reference, input_speeds).items()
    }


def complex_link_ratios(
    analysis: KinematicAnalysis,
    reference: str,
    input_speeds: Mapping[str, float] | None = None,
) -> dict[str, complex]:
    """Complex ratios ``ω_link/ω_reference`` of every link (seed 000 eq 5; the phase is the
    direction of the rotation vector in the sketch plane, seed 000 §2.5).

    1-DOF: from ``velocity_ratios([reference])``. More DOF: the ratios depend on the operating
    point, so ``input_speeds`` (link → signed speed, any one unit, for ``dof`` independent
    inputs) must be given; otherwise :class:`InputError` names the inputs needed.
    """
    g = analysis.graph
    if reference not in g.links:
        raise InputError(f"reference: unknown link {reference!r} (known: {', '.join(g.links)})")
    if reference == g.frame:
        raise InputError(f"reference: {reference!r} is the frame; it does not turn")
    if analysis.dof < 1:
        raise InputError(f"cfg: the mechanism has {analysis.dof} DOF; nothing turns")
    if input_speeds:
        omega = analysis.speeds(dict(input_speeds))
        w_ref = complex(omega[g.index(reference)])
        if abs(w_ref) == 0:
            raise InputError(
                f"reference: {reference!r} is at rest for input_speeds {dict(input_speeds)}"
            )
        return {lk: complex(omega[i]) / w_ref for i, lk in enumerate(g.links)}
    if analysis.dof > 1:
        cands = [lk for lk in g.links if lk != g.frame]
        raise InputError(
            f"cfg: the mechanism has {analysis.dof} degrees of freedom, so the link speeds are "
            f"not fixed ratios of '{reference}'; give input_speeds for {analysis.dof} "
            f"independent links (candidates: {', '.join(cands)})"
        )
    col = analysis.velocity_ratios([reference])[:, 0]  # per unit speed about ref's own axis
    col = col / col[g.index(reference)]  # ω_link / ω_reference
    return {lk: complex(col[i]) for i, lk in enumerate(g.links)}


def _bearing_orders_from_ratios(g: MechanismGraph, ratios: dict[str, complex]) -> dict[str, dict]:
    """Bearing lines from the link ratios (any DOF, planar rings; Harris' formulas via
    :func:`geardyn.bearings.frequencies.bearing_frequencies` on the relative speed)."""
    from geardyn.bearings.frequencies import bearing_frequencies

    out = {}
    for b in g.bearings:
        rel = abs(ratios[b.inner] - ratios[b.outer])
        bf = bearing_frequencies(
            rel, 0.0, b.n_elements, b.element_diameter, b.pitch_diameter, b.contact_angle
        )
        out[b.name] = {
            "BPFO": float(bf.bpfo),
            "BPFI": float(bf.bpfi),
            "BSF": float(bf.bsf),
            "FTF": float(bf.ftf),
            "inner": b.inner,
            "outer": b.outer,
        }
    return out


def _wheel_table(analysis: KinematicAnalysis) -> dict[str, dict]:
    """Wheel name → link, teeth, carrier (of its first mesh) and meshes."""
    g = analysis.graph
    wheels: dict[str, dict] = {}
    for mesh, k in zip(g.meshes, analysis.carriers, strict=True):
        for link, wheel, teeth in (
            (mesh.link_a, mesh.wheel_a, mesh.teeth_a),
            (mesh.link_b, mesh.wheel_b, mesh.teeth_b),
        ):
            key = wheel or f"{link}/z{teeth}"
            w = wheels.setdefault(key, {"link": link, "teeth": teeth, "carrier": k, "meshes": []})
            w["meshes"].append(mesh.name)
    return wheels


def _planetary(analysis: KinematicAnalysis, ratios: dict[str, complex]) -> list[PlanetaryStageInfo]:
    g = analysis.graph
    out = []
    for ps in g.planetary_sets:
        teeth = {m.name: m for m in g.meshes if m.stage == ps.name}
        p0 = ps.planets[0]
        tag = p0.split(".")[-1]
        sun_mesh = teeth.get(f"{ps.name}.sun-{tag}")
        ring_mesh = teeth.get(f"{ps.name}.ring-{tag}")
        if sun_mesh is None or ring_mesh is None:
            continue
        rc = ratios[ps.carrier]
        out.append(
            PlanetaryStageInfo(
                name=ps.name,
                sun=ps.sun,
                ring=ps.ring,
                carrier=ps.carrier,
                planets=tuple(ps.planets),
                sun_teeth=sun_mesh.teeth_a,
                ring_teeth=ring_mesh.teeth_a,
                planet_sun_teeth=sun_mesh.teeth_b,
                planet_ring_teeth=ring_mesh.teeth_b,
                planet_angles=tuple(ps.planet_angles),
                carrier_ratio=_real_ratio(rc),
                sun_ratio=_real_ratio(ratios[ps.sun] - rc),
                planet_ratio=_real_ratio(ratios[p0] - rc),
                ring_ratio=_real_ratio(ratios[ps.ring] - rc),
                ring_fixed=ps.ring == g.frame or ratios[ps.ring] == 0.0,
            )
        )
    return out


def _planet_links(analysis: KinematicAnalysis) -> set[str]:
    """Links held only by a moving carrier (planets): not shafts of their own."""
    g = analysis.graph
    holders: dict[str, set[str]] = {}
    for jt in g.joints:
        holders.setdefault(jt.link_a, set()).add(jt.link_b)
        holders.setdefault(jt.link_b, set()).add(jt.link_a)
    carriers = set(analysis.carriers) - {g.frame}
    return {lk for lk, h in holders.items() if len(h) == 1 and next(iter(h)) in carriers}


def machine_components(
    cfg: Mechanism | MechanismGraph | KinematicAnalysis,
    reference: str,
    input_speeds: Mapping[str, float] | None = None,
) -> Components:
    """Diagnosable components of a mechanism, referred to the ``reference`` link.

    ``cfg``: a :class:`~geardyn.config.Mechanism` (or ``GeardynConfig``), a
    :class:`~geardyn.kinematics.MechanismGraph` or a :class:`~geardyn.kinematics.KinematicAnalysis`.
    ``input_speeds``: only for mechanisms with more than one DOF (link → signed speed, any one
    unit): the ratios then hold at that operating point; default the config's
    ``input_speeds_rpm`` when ``cfg`` is a config.

    Shafts: every turning link except the frame and the planets, own angle its rotation, mesh
    orders the tooth counts of its fixed-axis wheels (carrier = frame). Wheels: own angle
    relative to the carrier of their meshes; kinds sun/planet/ring inside planetary stages
    (one planet component per planet; ``planet`` index), wheel otherwise. Bearings: BPFO/BPFI/
    BSF/FTF as orders of the reference, ratio of the rotating ring.
    """
    analysis = _as_analysis(cfg)
    g = analysis.graph
    if input_speeds is None and analysis.dof > 1:  # the config's operating point, if stated
        input_speeds = dict(getattr(cfg, "input_speeds_rpm", None) or {}) or None
    cr = complex_link_ratios(analysis, reference, input_speeds)
    ratios = {k: _real_ratio(v) for k, v in cr.items()}
    planets = _planet_links(analysis)
    stages = _planetary(analysis, cr)
    wheels = _wheel_table(analysis)
    stage_of = {}
    for st in stages:
        stage_of[f"{st.name}.sun"] = (st, "sun", None)
        stage_of[f"{st.name}.ring"] = (st, "ring", None)
        for i, p in enumerate(st.planets):
            stage_of[p] = (st, "planet", i)
    items: list[Component] = []
    # shafts
    for lk in g.links:
        if lk == g.frame or lk in planets or ratios[lk] == 0.0:
            continue
        fixed = [w for w, d in wheels.items() if d["link"] == lk and ratios[d["carrier"]] == 0.0]
        items.append(
            Component(
                name=lk,
                kind="shaft",
                link=lk,
                ratio=ratios[lk],
                mesh_orders=tuple(dict.fromkeys(wheels[w]["teeth"] for w in fixed)),
                others=tuple(fixed),
            )
        )
    # wheels
    for name, d in wheels.items():
        lk, k = d["link"], d["carrier"]
        rel = _real_ratio(cr[lk] - cr[k])
        if rel == 0.0:
            continue  # a wheel that does not turn relative to its carrier never meshes
        same = [
            w
            for w, e in wheels.items()
            if w != name and e["link"] == lk and e["carrier"] == k and e["teeth"] != d["teeth"]
        ]
        st, kind, idx = stage_of.get(name, stage_of.get(lk, (None, "wheel", None)))
        items.append(
            Component(
                name=name,
                kind=kind,
                link=lk,
                ratio=rel,
                mesh_orders=(d["teeth"],),
                other_orders=tuple(dict.fromkeys(wheels[w]["teeth"] for w in same)),
                teeth=d["teeth"],
                others=tuple(same),
                carrier=k,
                stage=st.name if st is not None else None,
                planet=idx,
            )
        )
    # bearings
    for name, d in _bearing_orders_from_ratios(g, cr).items():
        inner, outer = d["inner"], d["outer"]
        turning = inner if ratios[inner] != 0.0 else outer
        items.append(
            Component(
                name=name,
                kind="bearing",
                link=turning,
                ratio=_real_ratio(cr[inner] - cr[outer]),
                fault_orders={line: d[line] for line in BEARING_LINES},
            )
        )
    return Components(
        mechanism=g.name,
        reference=reference,
        ratios=ratios,
        items=items,
        planetary=stages,
        analysis=analysis,
        input_speeds=dict(input_speeds) if input_speeds else None,
    )


__all__ = [
    "BEARING_LINES",
    "KINDS",
    "Component",
    "Components",
    "PlanetaryStageInfo",
    "complex_link_ratios",
    "link_ratios",
    "machine_components",
]
