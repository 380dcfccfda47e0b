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
        problems: list[str] = []
        declared = [lk.name for lk in self.links]
        seen: set[str] = set()
        for name in declared:
            if name in seen:
                problems.append(f"links: duplicate link name '{name}'")
            seen.add(name)
        links = list(dict.fromkeys(declared))
        known = set(links)
        if self.frame not in known:
            problems.append(f"frame: unknown link '{self.frame}' (declare it under links)")

        def need(link: str, where: str) -> None:
            if link not in known:
                problems.append(f"{where}: unknown link '{link}' (declare it under links)")

        meshes: list[GearMesh] = []
        joints: list[TurningJoint] = []
        bearings: list[RollingBearing] = []
        psets: list[PlanetarySet] = []
        pair_names: set[str] = set()

        def add_mesh(m: GearMesh, where: str) -> None:
            if m.name in pair_names:
                problems.append(f"{where}: duplicate gear pair name '{m.name}'")
            pair_names.add(m.name)
            meshes.append(m)

        # Axis levels are labels joined by a union-find: a stage saying "these links are coaxial"
        # merges the labels they already carry, so a shaft shared by several stages keeps one
        # axis whatever the declaration order (issue 11). Labels typed by the user (turning
        # pairs, a stage's ``axis``) are never merged with each other: that stays an error.
        joint_axis: dict[frozenset[str], str] = {}
        parent: dict[str, str] = {}
        explicit: set[str] = {str(tp.axis) for tp in self.turning_pairs}
        explicit |= {st.axis for st in self.planetary if st.axis is not None}

        def find(label: str) -> str:
            parent.setdefault(label, label)
            while parent[label] != label:
                parent[label] = parent[parent[label]]
                label = parent[label]
            return label

        def merge(a: str, b: str) -> bool:
            """Join two axis labels; False when both are distinct user-given labels."""
            ra, rb = find(a), find(b)
            if ra == rb:
                return True
            if ra in explicit and rb in explicit:
                return False
            if rb in explicit:
                ra, rb = rb, ra
            parent[rb] = ra  # a user-given label, else the stage's own, names the merged axis
            return True

        def add_joint(a: str, b: str, axis: str, where: str, reuse: bool = False) -> str:
            key = frozenset((a, b))
            if key in joint_axis:
                got = find(joint_axis[key])
                if reuse:
                    return got
                if got != find(axis):
                    problems.append(
                        f"{where}: turning pair {a}–{b} given twice with different axis levels "
                        f"('{got}' and '{axis}'); two links turn about one axis only"
                    )
                return got
            find(axis)
            joint_axis[key] = axis
            joints.append(TurningJoint(a, b, axis))
            return find(axis)

        # general form
        for i, tp in enumerate(self.turning_pairs):
            where = f"turning_pairs[{i}] ({tp.links[0]}–{tp.links[1]})"
            for lk in tp.links:
                need(lk, where)
            add_joint(tp.links[0], tp.links[1], str(tp.axis), where)
        for i, gp in enumerate(self.gear_pairs):
            where = f"gear_pairs[{i}] '{gp.label}'"
            need(gp.a.link, where)
            need(gp.b.link, where)
            add_mesh(
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

        def shaft_axis(link: str, support: str, default: str, where: str) -> str:
            return add_joint(link, support, default, where, reuse=True)

        # parallel and bevel stages: each wheel turns on its own fixed axis in the support
        for i, st in enumerate([*self.parallel, *self.bevel]):
            kind = "parallel" if isinstance(st, ParallelStage) else "bevel"
            where = f"{kind} stage '{st.name}'"
            support = st.support or self.frame
            need(support, where)
            need(st.a.link, where)
            need(st.b.link, where)
            for side in (st.a, st.b):
                if side.link != support:
                    shaft_axis(side.link, support, f"{st.name}.{side.link}.axis{i}", where)
            if isinstance(st, ParallelStage):
                ta = math.pi if st.internal == "a" else 0.0
                tb = math.pi if st.internal == "b" else 0.0
            else:
                ta, tb = st.pitch_angles()
            add_mesh(
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

        # planetary stages
        for st in self.planetary:
            where = f"planetary stage '{st.name}'"
            support = st.support or self.frame
            need(support, where)
            for lk in (st.sun, st.ring, st.carrier):
                need(lk, where)
            central = [x for x in (st.sun, st.ring, st.carrier) if x != support]
            axis = st.axis or f"{st.name}.central"
            for x in central:
                got = add_joint(x, support, axis, where, reuse=True)
                if not merge(axis, got):
                    problems.append(
                        f"{where}: '{x}' already turns in '{support}' about axis '{find(got)}', "
                        f"not the stage's central axis '{find(axis)}' (both axis levels are "
                        "given explicitly; the central members of a stage share one axis)"
                    )
            planets = st.planet_names()
            for p in planets:
                if p in known:
                    problems.append(f"{where}: planet link name '{p}' clashes with a declared link")
                links.append(p)
                known.add(p)
                add_joint(p, st.carrier, f"{p}.pin", where)
                add_mesh(
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
                add_mesh(
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
                    bearings.append(
                        st.planet_bearing.rolling_bearing(f"{p}.bearing", st.carrier, p)
                    )
            psets.append(
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

        # canonical axis labels, then: the two wheels of a parallel or bevel stage may not have
        # been made coaxial by a planetary stage
        joints = [TurningJoint(j.link_a, j.link_b, find(j.axis)) for j in joints]
        for st in [*self.parallel, *self.bevel]:
            support = st.support or self.frame
            ka, kb = frozenset((st.a.link, support)), frozenset((st.b.link, support))
            if ka in joint_axis and kb in joint_axis and find(joint_axis[ka]) == find(
                joint_axis[kb]
            ):
                problems.append(
                    f"stage '{st.name}': '{st.a.link}' and '{st.b.link}' turn about the same axis "
                    f"'{find(joint_axis[ka])}' in '{support}' (a planetary stage makes them "
                    "coaxial), so they cannot mesh as a parallel or bevel pair"
                )

        # bearings on turning pairs
        bnames: set[str] = set()
        for b in self.bearings:
            where = f"bearing '{b.name}'"
            if b.name in bnames:
                problems.append(f"{where}: duplicate bearing name")
            bnames.add(b.name)
            need(b.inner, where)
            need(b.outer, where)
            if (
                b.inner in known
                and b.outer in known
                and frozenset((b.inner, b.outer)) not in joint_axis
            ):
                problems.append(
                    f"{where}: there is no turning pair between '{b.inner}' and '{b.outer}' "
                    "(a bearing sits on a turning pair)"
                )
            bearings.append(b.rolling_bearing(b.name, b.inner, b.outer))

        # every moving link must be held by a turning pair
        held = {j.link_a for j in joints} | {j.link_b for j in joints}
        for lk in links:
            if lk != self.frame and lk not in held:
                problems.append(
                    f"link '{lk}': has no turning pair, so nothing holds it (add a turning pair "
                    "or remove the link)"
                )
        for name in self.input_speeds_rpm:
            if name not in known:
                problems.append(f"input_speeds_rpm: unknown link '{name}'")
            elif name == self.frame:
                problems.append(f"input_speeds_rpm: '{name}' is the frame (its speed is 0)")
        graph = MechanismGraph(
            name=self.name,
            frame=self.frame,
            links=links,
            meshes=meshes,
            joints=joints,
            bearings=bearings,
            planetary_sets=psets,
        )
        if not problems:
            # carriers (seed 000 eq 1) are part of validity: report them at load time
            from geardyn.kinematics.willis import reference_link, turning_neighbourhood

            s = turning_neighbourhood(graph)
            for m in meshes:
                try:
                    reference_link(m, s)
                except KinematicsError as exc:
                    problems.append(str(exc))
        return graph, problems
