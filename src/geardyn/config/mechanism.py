"""Mechanism description (the ``[mechanism]`` part of a geardyn config), validated by pydantic.

The general form follows Penaud et al. 2012, §2: named links, gear pairs with tooth counts and pitch
angles (complex weights ``N·e^{iθ}``), turning pairs grouped by axis level, the frame link and
optional rolling bearings. Conveniences (planetary, parallel and bevel stages) expand into the
same graph (:meth:`Mechanism.graph`).

Units: tooth counts are integers; angles are in degrees in the config (``*_deg`` fields) and in
radians in the graph; lengths in metres (``*_m`` fields); speeds in rpm (``*_rpm``).
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    StrictInt,
    field_validator,
    model_validator,
)

from geardyn.bearings.frequencies import check_bearing_geometry
from geardyn.errors import ConfigError, KinematicsError
from geardyn.kinematics.graph import (
    GearMesh,
    MechanismGraph,
    PlanetarySet,
    RollingBearing,
    TurningJoint,
)


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


def _teeth(v: object) -> object:
    # TOML floats such as 13.0 are accepted only when integral; 13.5 is rejected by StrictInt.
    if isinstance(v, float) and v.is_integer():
        return int(v)
    if isinstance(v, float | str):
        raise ValueError(f"teeth must be a whole number (got {v!r})")
    return v


#: Most teeth of one wheel: the largest gears built (girth gears of mills and kilns, ring gears
#: of slewing drives, up to ~15 m) have a few hundred teeth; 10 000 leaves a factor of ten and
#: refuses counts typed wrong (1e18 teeth would make every hunting period and table overflow).
MAX_TEETH = 10_000

Teeth = Annotated[StrictInt, BeforeValidator(_teeth),
                  Field(ge=1, le=MAX_TEETH, description="number of teeth")]


class Link(_Model):
    """A rigid link (shaft, housing, carrier, planet, ...)."""

    name: str = Field(min_length=1, description="unique link name")
    description: str = ""


def _link(v: object) -> object:
    return {"name": v} if isinstance(v, str) else v


class GearSide(_Model):
    """One side of a gear pair: the wheel on ``link`` (Penaud et al. 2012, §2.2)."""

    link: str = Field(description="link carrying this wheel")
    teeth: Teeth
    internal: bool = Field(False, description="internal (ring) gear")
    pitch_angle_deg: float | None = Field(
        None,
        description="pitch angle θ (deg, positive clockwise) from the gear axis to the tooth axis "
        "in contact; default 0 for external, 180 for internal gears (Penaud et al. 2012, §2.2)",
    )
    wheel: str | None = Field(
        None, description="name of the toothed wheel (default '<link>/z<teeth>')"
    )

    @model_validator(mode="after")
    def _check_angle(self) -> GearSide:
        if self.pitch_angle_deg is not None:
            a = abs(self.pitch_angle_deg)
            if a > 180:
                raise ValueError(f"pitch_angle_deg {self.pitch_angle_deg} must be within ±180")
            if self.internal and a <= 90:
                raise ValueError(
                    f"pitch_angle_deg {self.pitch_angle_deg}: an internal gear needs "
                    "90 < |θ| ≤ 180 (Penaud et al. 2012, §2.2)"
                )
            if not self.internal and a >= 90:
                raise ValueError(
                    f"pitch_angle_deg {self.pitch_angle_deg}: an external gear needs |θ| < 90 "
                    "(Penaud et al. 2012, §2.2); set internal = true for an internal gear"
                )
        return self

    @property
    def theta(self) -> float:
        """Pitch angle in radians."""
        if self.pitch_angle_deg is not None:
            return math.radians(self.pitch_angle_deg)
        return math.pi if self.internal else 0.0

    @property
    def wheel_name(self) -> str:
        return self.wheel or f"{self.link}/z{self.teeth}"


class GearPair(_Model):
    """A gear pair between two links (general form, Penaud et al. 2012, §2.2)."""

    name: str | None = Field(None, description="pair name (default 'a-b')")
    a: GearSide
    b: GearSide

    @model_validator(mode="after")
    def _check(self) -> GearPair:
        if self.a.link == self.b.link:
            raise ValueError(f"a link cannot mesh with itself ('{self.a.link}')")
        if self.a.internal and self.b.internal:
            raise ValueError("two internal gears cannot mesh")
        return self

    @property
    def label(self) -> str:
        return self.name or f"{self.a.link}-{self.b.link}"


class BearingGeometry(_Model):
    """Rolling-bearing geometry (for BPFO/BPFI/BSF/FTF)."""

    kind: Literal["ball", "roller"] = "ball"
    n_elements: StrictInt = Field(description="number of rolling elements")
    element_diameter_m: float = Field(description="ball/roller diameter d (m)")
    pitch_diameter_m: float = Field(description="pitch diameter D (m)")
    contact_angle_deg: float = Field(0.0, description="contact angle α (deg)")

    @model_validator(mode="after")
    def _check(self) -> BearingGeometry:
        problems = check_bearing_geometry(
            self.n_elements,
            self.element_diameter_m,
            self.pitch_diameter_m,
            math.radians(self.contact_angle_deg),
        )
        if problems:
            raise ValueError("; ".join(problems))
        return self

    def rolling_bearing(self, name: str, inner: str, outer: str) -> RollingBearing:
        """The graph object for this geometry mounted between ``inner`` and ``outer``."""
        return RollingBearing(
            name=name,
            inner=inner,
            outer=outer,
            n_elements=self.n_elements,
            element_diameter=self.element_diameter_m,
            pitch_diameter=self.pitch_diameter_m,
            contact_angle=math.radians(self.contact_angle_deg),
            kind=self.kind,
        )


class Bearing(BearingGeometry):
    """A rolling bearing on the turning pair between ``inner`` and ``outer``."""

    name: str
    inner: str = Field(description="link carrying the inner ring")
    outer: str = Field(description="link carrying the outer ring")


class TurningPair(_Model):
    """A turning pair (revolute joint) between two links on an axis level (Penaud et al. 2012,
    §2.1)."""

    links: tuple[str, str]
    axis: str | int = Field(
        description="axis level: turning pairs on the same level and touching form a multiple "
        "turning pair (Penaud et al. 2012, §2.1)"
    )

    @field_validator("links")
    @classmethod
    def _distinct(cls, v: tuple[str, str]) -> tuple[str, str]:
        if v[0] == v[1]:
            raise ValueError(f"a turning pair needs two different links (got '{v[0]}' twice)")
        return v


class PlanetaryStage(_Model):
    """A simple or compound (stepped-planet) planetary stage.

    Expands into ``n_planets`` planet links named ``<name>.planet<i>``, each meshing the sun and
    the ring, turning on the carrier; sun, ring and carrier turn about a common central axis on
    ``support`` (default: the frame). A link among sun/ring/carrier equal to ``support`` is
    simply held by it.
    """

    name: str
    sun: str
    ring: str
    carrier: str
    sun_teeth: Teeth
    ring_teeth: Teeth
    planet_teeth: Teeth | tuple[Teeth, Teeth] = Field(
        description="planet teeth, or [teeth meshing sun, teeth meshing ring] for stepped planets"
    )
    n_planets: StrictInt = Field(ge=1)
    planet_angles_deg: list[float] | None = Field(
        None, description="planet positions (deg); default equally spaced"
    )
    support: str | None = Field(None, description="link the central members turn in (frame)")
    axis: str | None = Field(None, description="axis level of the central axis")
    planet_bearing: BearingGeometry | None = Field(
        None, description="bearing of each planet on its pin (inner ring on the carrier)"
    )

    @property
    def stepped(self) -> bool:
        return isinstance(self.planet_teeth, tuple)

    @property
    def planet_sun_teeth(self) -> int:
        return self.planet_teeth[0] if isinstance(self.planet_teeth, tuple) else self.planet_teeth

    @property
    def planet_ring_teeth(self) -> int:
        return self.planet_teeth[1] if isinstance(self.planet_teeth, tuple) else self.planet_teeth

    @model_validator(mode="after")
    def _check(self) -> PlanetaryStage:
        names = {"sun": self.sun, "ring": self.ring, "carrier": self.carrier}
        if len(set(names.values())) != 3:
            raise ValueError(f"sun, ring and carrier must be three different links (got {names})")
        n = self.n_planets
        zs, zr = self.sun_teeth, self.ring_teeth
        zps, zpr = self.planet_sun_teeth, self.planet_ring_teeth
        if self.planet_angles_deg is None:
            # Equal spacing: the planets can be assembled at 2π/n only if the assembly condition
            # holds (simple: (z_s + z_r)/n integer; stepped: (z_s·z_pr + z_r·z_ps)/(n·gcd) integer).
            if not self.stepped:
                if (zs + zr) % n:
                    raise ValueError(
                        f"{n} planets cannot be equally spaced: (sun_teeth + ring_teeth)/n_planets "
                        f"= ({zs} + {zr})/{n} = {(zs + zr) / n:.4g} is not an integer"
                    )
            else:
                num = zs * zpr + zr * zps
                den = n * math.gcd(zps, zpr)
                if num % den:
                    raise ValueError(
                        f"{n} identical stepped planets cannot be equally spaced: "
                        f"(z_s·z_pr + z_r·z_ps)/"
                        f"(n·gcd(z_ps, z_pr)) = {num}/{den} is not an integer"
                    )
            # Neighbouring planets must clear: centre distance 2a·sin(π/n) > tip diameter,
            # with standard addendum (h_a* = 1): (z_s + z_p)·sin(π/n) > z_p + 2.
            if n >= 2 and not self.stepped and (zs + zps) * math.sin(math.pi / n) <= zps + 2:
                raise ValueError(
                    f"{n} planets of {zps} teeth do not fit around a {zs}-tooth sun: adjacent "
                    f"planet tips overlap ((z_s + z_p)·sin(π/n) = "
                    f"{(zs + zps) * math.sin(math.pi / n):.3g} ≤ z_p + 2 = {zps + 2})"
                )
        elif len(self.planet_angles_deg) != n:
            raise ValueError(
                f"planet_angles_deg has {len(self.planet_angles_deg)} entries for n_planets = {n}"
            )
        if not self.stepped and zr <= zs + zps:
            raise ValueError(
                f"ring_teeth {zr} must exceed sun_teeth + planet_teeth = {zs + zps} "
                "(the ring must surround sun and planets)"
            )
        return self

    def angles(self) -> list[float]:
        """Planet angles in radians."""
        if self.planet_angles_deg is not None:
            return [math.radians(a) for a in self.planet_angles_deg]
        return [2 * math.pi * i / self.n_planets for i in range(self.n_planets)]

    def planet_names(self) -> list[str]:
        return [f"{self.name}.planet{i + 1}" for i in range(self.n_planets)]


class StageSide(_Model):
    """A wheel of a parallel or bevel stage."""

    link: str
    teeth: Teeth
    wheel: str | None = None


class ParallelStage(_Model):
    """Two wheels on parallel fixed axes (external, or internal if ``internal`` names a side)."""

    name: str
    a: StageSide
    b: StageSide
    internal: Literal["a", "b"] | None = Field(None, description="side that is an internal gear")
    support: str | None = Field(None, description="link both shafts turn in (default frame)")

    @model_validator(mode="after")
    def _check(self) -> ParallelStage:
        if self.a.link == self.b.link:
            raise ValueError(f"a link cannot mesh with itself ('{self.a.link}')")
        return self


class BevelStage(_Model):
    """Two bevel wheels on intersecting fixed axes at ``shaft_angle_deg`` (default 90°).

    Pitch-cone angles follow from the tooth counts, ``tan δ_a = sin Σ/(N_b/N_a + cos Σ)``,
    ``δ_b = Σ − δ_a``; the Penaud et al. 2012 weights are ``θ_a = −δ_a``, ``θ_b = +δ_b``, so the
    output
    axis is turned by the shaft angle in the sketch plane. A negative shaft angle turns it the
    other way.
    """

    name: str
    a: StageSide
    b: StageSide
    shaft_angle_deg: float = 90.0
    support: str | None = None

    @model_validator(mode="after")
    def _check(self) -> BevelStage:
        if self.a.link == self.b.link:
            raise ValueError(f"a link cannot mesh with itself ('{self.a.link}')")
        if not 0 < abs(self.shaft_angle_deg) < 180:
            raise ValueError(f"shaft_angle_deg {self.shaft_angle_deg} must be in (0, 180) in size")
        return self

    def pitch_angles(self) -> tuple[float, float]:
        """(θ_a, θ_b) in radians, Penaud et al. 2012 sign convention."""
        sigma = math.radians(abs(self.shaft_angle_deg))
        da = math.atan2(math.sin(sigma), self.b.teeth / self.a.teeth + math.cos(sigma))
        db = sigma - da
        sign = 1.0 if self.shaft_angle_deg > 0 else -1.0
        return -sign * da, sign * db


class Mechanism(_Model):
    """A geared mechanism: general graph plus stage conveniences (Penaud et al. 2012, §2)."""

    name: str = "mechanism"
    frame: str = Field(description="the fixed link (ω = 0), first row of M (Penaud et al. "
                       "2012, §2.4)")
    links: list[Annotated[Link, BeforeValidator(_link)]] = Field(default_factory=list)
    gear_pairs: list[GearPair] = Field(default_factory=list)
    turning_pairs: list[TurningPair] = Field(default_factory=list)
    bearings: list[Bearing] = Field(default_factory=list)
    planetary: list[PlanetaryStage] = Field(default_factory=list)
    parallel: list[ParallelStage] = Field(default_factory=list)
    bevel: list[BevelStage] = Field(default_factory=list)
    input_speeds_rpm: dict[str, float] = Field(
        default_factory=dict,
        description="default input link speeds (rpm, signed about each link's own axis)"
    )

    @model_validator(mode="after")
    def _check_graph(self) -> Mechanism:
        # Build the graph once so reference problems are reported at load time.
        problems = self._problems()
        if problems:
            # one problem per line; the loader turns each into its own message
            raise ValueError("\n".join(problems))
        return self

    # ---- expansion ----------------------------------------------------------------------
    def graph(self) -> MechanismGraph:
        """The general mechanism graph (conveniences expanded)."""
        return self._graph

    @cached_property
    def _graph(self) -> MechanismGraph:
        g, problems = self._expand()
        if problems:
            raise ConfigError(problems)
        return g

    def _problems(self) -> list[str]:
        try:
            _, problems = self._expand()
        except KinematicsError as exc:  # pragma: no cover - defensive
            return [str(exc)]
        return problems

    def _expand(self) -> tuple[MechanismGraph, list[str]]:
        """The mechanism graph (links, meshes, turning pairs, bearings, planetary sets) of
        this description and its problems, one message per problem, in declaration order
        (Penaud et al. 2012, §2: links, turning pairs grouped by axis level, gear pairs)."""
        g = _GraphExpansion(self)
        g.general_form()
        g.fixed_axis_stages()
        g.planetary_stages()
        g.check_fixed_axis_pairs_not_coaxial()
        g.mounted_bearings()
        g.held_links_and_inputs()
        graph = g.graph()
        g.check_carriers(graph)
        return graph, g.problems


class _GraphExpansion:
    """The expansion of a :class:`Mechanism` into its :class:`MechanismGraph`, section by
    section, collecting every problem (one message each, naming the item) instead of stopping
    at the first.

    Axis levels are labels joined by a union-find: a stage saying "these links are coaxial"
    merges the labels they already carry, so a shaft shared by several stages keeps one axis
    whatever the declaration order (issue 11). Labels typed by the user (turning pairs, a
    stage's ``axis``) are never merged with each other: that stays an error."""

    def __init__(self, mech: Mechanism) -> None:
        self.mech = mech
        self.problems: list[str] = []
        declared = [lk.name for lk in mech.links]
        seen: set[str] = set()
        for name in declared:
            if name in seen:
                self.problems.append(f"links: duplicate link name '{name}'")
            seen.add(name)
        self.links = list(dict.fromkeys(declared))
        self.known = set(self.links)
        if mech.frame not in self.known:
            self.problems.append(f"frame: unknown link '{mech.frame}' (declare it under links)")
        self.meshes: list[GearMesh] = []
        self.joints: list[TurningJoint] = []
        self.bearings: list[RollingBearing] = []
        self.psets: list[PlanetarySet] = []
        self.pair_names: set[str] = set()
        self.joint_axis: dict[frozenset[str], str] = {}
        self.parent: dict[str, str] = {}
        self.explicit: set[str] = {str(tp.axis) for tp in mech.turning_pairs}
        self.explicit |= {st.axis for st in mech.planetary if st.axis is not None}

    # ---- bookkeeping ------------------------------------------------------------------------
    def need(self, link: str, where: str) -> None:
        if link not in self.known:
            self.problems.append(f"{where}: unknown link '{link}' (declare it under links)")

    def add_mesh(self, m: GearMesh, where: str) -> None:
        if m.name in self.pair_names:
            self.problems.append(f"{where}: duplicate gear pair name '{m.name}'")
        self.pair_names.add(m.name)
        self.meshes.append(m)

    def find(self, label: str) -> str:
        parent = self.parent
        parent.setdefault(label, label)
        while parent[label] != label:
            parent[label] = parent[parent[label]]
            label = parent[label]
        return label

    def merge(self, a: str, b: str) -> bool:
        """Join two axis labels; False when both are distinct user-given labels."""
        ra, rb = self.find(a), self.find(b)
        if ra == rb:
            return True
        if ra in self.explicit and rb in self.explicit:
            return False
        if rb in self.explicit:
            ra, rb = rb, ra
        self.parent[rb] = ra  # a user-given label, else the stage's own, names the merged axis
        return True

    def add_joint(self, a: str, b: str, axis: str, where: str, reuse: bool = False) -> str:
        key = frozenset((a, b))
        if key in self.joint_axis:
            got = self.find(self.joint_axis[key])
            if reuse:
                return got
            if got != self.find(axis):
                self.problems.append(
                    f"{where}: turning pair {a}–{b} given twice with different axis levels "
                    f"('{got}' and '{axis}'); two links turn about one axis only"
                )
            return got
        self.find(axis)
        self.joint_axis[key] = axis
        self.joints.append(TurningJoint(a, b, axis))
        return self.find(axis)

    # ---- sections ---------------------------------------------------------------------------
    def general_form(self) -> None:
        """Turning pairs on their axis levels and gear pairs with their pitch angles."""
        for i, tp in enumerate(self.mech.turning_pairs):
            where = f"turning_pairs[{i}] ({tp.links[0]}–{tp.links[1]})"
            for lk in tp.links:
                self.need(lk, where)
            self.add_joint(tp.links[0], tp.links[1], str(tp.axis), where)
        for i, gp in enumerate(self.mech.gear_pairs):
            where = f"gear_pairs[{i}] '{gp.label}'"
            self.need(gp.a.link, where)
            self.need(gp.b.link, where)
            self.add_mesh(
                GearMesh(
                    name=gp.label,
                    link_a=gp.a.link,
                    link_b=gp.b.link,
                    teeth_a=gp.a.teeth,
                    teeth_b=gp.b.teeth,
                    theta_a=gp.a.theta,
                    theta_b=gp.b.theta,
                    wheel_a=gp.a.wheel_name,
                    wheel_b=gp.b.wheel_name,
                ),
                where,
            )

    def fixed_axis_stages(self) -> None:
        """Parallel and bevel stages: each wheel turns on its own fixed axis in the support."""
        for i, st in enumerate([*self.mech.parallel, *self.mech.bevel]):
            kind = "parallel" if isinstance(st, ParallelStage) else "bevel"
            where = f"{kind} stage '{st.name}'"
            support = st.support or self.mech.frame
            self.need(support, where)
            self.need(st.a.link, where)
            self.need(st.b.link, where)
            for side in (st.a, st.b):
                if side.link != support:
                    self.add_joint(side.link, support, f"{st.name}.{side.link}.axis{i}", where,
                                   reuse=True)
            if isinstance(st, ParallelStage):
                ta = math.pi if st.internal == "a" else 0.0
                tb = math.pi if st.internal == "b" else 0.0
            else:
                ta, tb = st.pitch_angles()
            self.add_mesh(
                GearMesh(
                    name=st.name,
                    link_a=st.a.link,
                    link_b=st.b.link,
                    teeth_a=st.a.teeth,
                    teeth_b=st.b.teeth,
                    theta_a=ta,
                    theta_b=tb,
                    wheel_a=st.a.wheel or f"{st.a.link}/z{st.a.teeth}",
                    wheel_b=st.b.wheel or f"{st.b.link}/z{st.b.teeth}",
                    stage=st.name,
                ),
                where,
            )

    def planetary_stages(self) -> None:
        """Planetary stages: central members on one axis in the support, each planet on its
        pin in the carrier, meshing with the sun (external) and the ring (internal)."""
        for st in self.mech.planetary:
            where = f"planetary stage '{st.name}'"
            support = st.support or self.mech.frame
            self.need(support, where)
            for lk in (st.sun, st.ring, st.carrier):
                self.need(lk, where)
            self._central_axis(st, support, where)
            planets = st.planet_names()
            for p in planets:
                self._planet(st, p, where)
            self.psets.append(
                PlanetarySet(
                    name=st.name,
                    sun=st.sun,
                    ring=st.ring,
                    carrier=st.carrier,
                    planets=tuple(planets),
                    planet_angles=tuple(st.angles()),
                    sun_wheel=f"{st.name}.sun",
                    ring_wheel=f"{st.name}.ring",
                )
            )

    def _central_axis(self, st: PlanetaryStage, support: str, where: str) -> None:
        central = [x for x in (st.sun, st.ring, st.carrier) if x != support]
        axis = st.axis or f"{st.name}.central"
        for x in central:
            got = self.add_joint(x, support, axis, where, reuse=True)
            if not self.merge(axis, got):
                self.problems.append(
                    f"{where}: '{x}' already turns in '{support}' about axis "
                    f"'{self.find(got)}', not the stage's central axis '{self.find(axis)}' (both "
                    "axis levels are given explicitly; the central members of a stage share one "
                    "axis)"
                )

    def _planet(self, st: PlanetaryStage, p: str, where: str) -> None:
        if p in self.known:
            self.problems.append(f"{where}: planet link name '{p}' clashes with a declared link")
        self.links.append(p)
        self.known.add(p)
        self.add_joint(p, st.carrier, f"{p}.pin", where)
        self.add_mesh(
            GearMesh(
                name=f"{st.name}.sun-{p.split('.')[-1]}",
                link_a=st.sun,
                link_b=p,
                teeth_a=st.sun_teeth,
                teeth_b=st.planet_sun_teeth,
                theta_a=0.0,
                theta_b=0.0,
                wheel_a=f"{st.name}.sun",
                wheel_b=f"{p}/z{st.planet_sun_teeth}",
                stage=st.name,
            ),
            where,
        )
        self.add_mesh(
            GearMesh(
                name=f"{st.name}.ring-{p.split('.')[-1]}",
                link_a=st.ring,
                link_b=p,
                teeth_a=st.ring_teeth,
                teeth_b=st.planet_ring_teeth,
                theta_a=math.pi,
                theta_b=0.0,
                wheel_a=f"{st.name}.ring",
                wheel_b=f"{p}/z{st.planet_ring_teeth}",
                stage=st.name,
            ),
            where,
        )
        if st.planet_bearing is not None:
            self.bearings.append(st.planet_bearing.rolling_bearing(f"{p}.bearing", st.carrier, p))

    def check_fixed_axis_pairs_not_coaxial(self) -> None:
        """Canonical axis labels; the two wheels of a parallel or bevel stage may not have been
        made coaxial by a planetary stage."""
        find, joint_axis = self.find, self.joint_axis
        self.joints = [TurningJoint(j.link_a, j.link_b, find(j.axis)) for j in self.joints]
        for st in [*self.mech.parallel, *self.mech.bevel]:
            support = st.support or self.mech.frame
            ka, kb = frozenset((st.a.link, support)), frozenset((st.b.link, support))
            if ka in joint_axis and kb in joint_axis and find(joint_axis[ka]) == find(
                joint_axis[kb]
            ):
                self.problems.append(
                    f"stage '{st.name}': '{st.a.link}' and '{st.b.link}' turn about the same axis "
                    f"'{find(joint_axis[ka])}' in '{support}' (a planetary stage makes them "
                    "coaxial), so they cannot mesh as a parallel or bevel pair"
                )

    def mounted_bearings(self) -> None:
        """Bearings sit on turning pairs (unique names)."""
        bnames: set[str] = set()
        for b in self.mech.bearings:
            where = f"bearing '{b.name}'"
            if b.name in bnames:
                self.problems.append(f"{where}: duplicate bearing name")
            bnames.add(b.name)
            self.need(b.inner, where)
            self.need(b.outer, where)
            if (
                b.inner in self.known
                and b.outer in self.known
                and frozenset((b.inner, b.outer)) not in self.joint_axis
            ):
                self.problems.append(
                    f"{where}: there is no turning pair between '{b.inner}' and '{b.outer}' "
                    "(a bearing sits on a turning pair)"
                )
            self.bearings.append(b.rolling_bearing(b.name, b.inner, b.outer))

    def held_links_and_inputs(self) -> None:
        """Every moving link held by a turning pair; input speeds on known, moving links."""
        held = {j.link_a for j in self.joints} | {j.link_b for j in self.joints}
        for lk in self.links:
            if lk != self.mech.frame and lk not in held:
                self.problems.append(
                    f"link '{lk}': has no turning pair, so nothing holds it (add a turning pair "
                    "or remove the link)"
                )
        for name in self.mech.input_speeds_rpm:
            if name not in self.known:
                self.problems.append(f"input_speeds_rpm: unknown link '{name}'")
            elif name == self.mech.frame:
                self.problems.append(f"input_speeds_rpm: '{name}' is the frame (its speed is 0)")

    def graph(self) -> MechanismGraph:
        return MechanismGraph(
            name=self.mech.name,
            frame=self.mech.frame,
            links=self.links,
            meshes=self.meshes,
            joints=self.joints,
            bearings=self.bearings,
            planetary_sets=self.psets,
        )

    def check_carriers(self, graph: MechanismGraph) -> None:
        """Carriers (Penaud et al. 2012, eq 1) are part of validity: reported at load time."""
        if self.problems:
            return
        from geardyn.kinematics.willis import reference_link, turning_neighbourhood

        s = turning_neighbourhood(graph)
        for m in self.meshes:
            try:
                reference_link(m, s)
            except KinematicsError as exc:
                self.problems.append(str(exc))
