"""Gear-geometry section of a config: ``[[gear_geometry]]`` entries attached to named gear pairs.

Each entry names a gear pair of the mechanism in ``pair``:

* a general pair (``gear_pairs[].name``, default ``'<link a>-<link b>'``) or a parallel stage
  (its ``name``);
* a planetary mesh ``'<stage>.sun-planet<i>'`` / ``'<stage>.ring-planet<i>'``, or
  ``'<stage>.sun-planet'`` / ``'<stage>.ring-planet'`` (no index) for every planet of the stage.

Tooth counts and which side is internal come from the mechanism; the entry's ``a``/``b`` blocks
describe the wheels on the pair's sides ``a``/``b`` (for planetary meshes: a = sun or ring,
b = planet). The stiffness model always takes the external wheel as its pinion: when side a
is internal (ring meshes), the sides are swapped internally and the stiffness table's angle is
the rotation of the planet. Units: metres (``*_m``), degrees (``*_deg``), pascals (``*_pa``),
newton-metres (``*_nm``). Bevel stages are not supported (cylindrical gears only).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, StrictInt

from geardyn.errors import ConfigError


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class WheelGeometry(_Model):
    """One wheel of a pair (sizes in m)."""

    profile_shift: float = Field(0.0, ge=-1.5, le=1.5, description="profile shift coefficient x")
    addendum_coef: float = Field(1.0, gt=0, le=2.0, description="h_a* (× normal module)")
    dedendum_coef: float = Field(1.25, gt=0, le=2.5, description="h_f* (× normal module)")
    tip_radius_m: float | None = Field(None, gt=0, description="tip radius override (m)")
    root_radius_m: float | None = Field(None, gt=0, description="root radius override (m)")
    rim_radius_m: float | None = Field(
        None, gt=0, description="bore radius (external) or outer rim radius (internal) (m)"
    )
    form_radius_m: float | None = Field(
        None, ge=0, description="radius where the usable involute starts (m); 0 = base circle"
    )
    tip_round_m: float = Field(0.0, ge=0, description="tip edge round radius (m)")
    root_fillet: Literal["involute", "trochoid"] = Field(
        "involute", description="flank below the involute in the PE stiffness: 'involute' "
        "(extended to the root, as the Thibault et al. 2024 / Wang 2010 tables) or 'trochoid' "
        "(the fillet cut by "
        "the rack tip, Sainsot root angle θ_f = b1/r)")
    rack_tip_radius_m: float | None = Field(
        None, gt=0, description="generating rack tip radius ρ_fP (m; trochoid fillet; default "
        "the full round of the basic rack)")
    normal_module_m: float | None = Field(
        None,
        gt=0,
        description="module of this wheel's tool if different (m); must give the same base pitch",
    )
    normal_pressure_angle_deg: float | None = Field(None, gt=0, lt=45)
    youngs_modulus_pa: float = Field(2.06e11, gt=0, description="Young's modulus (Pa)")
    poisson_ratio: float = Field(0.3, gt=0, lt=0.5, description="Poisson ratio")
    density_kg_m3: float = Field(7850.0, gt=0, description="density (kg/m³)")


class CrackConfig(_Model):
    """Root crack (Thibault et al. 2024, eq 14): on ``gear`` side a/b of the pair, tooth index
    from 0."""

    gear: Literal["a", "b"] = "b"
    tooth: StrictInt = Field(0, ge=0)
    depth_m: float = Field(gt=0, description="crack depth q0 (m)")
    angle_deg: float = Field(
        45.0, gt=0, lt=90, description="crack angle to the tooth perpendicular"
    )
    radius_m: float | None = Field(None, gt=0, description="start radius (m); default root circle")
    width_m: float | None = Field(None, gt=0, description="axial crack extent (m); default face")
    law: Literal["uniform", "linear", "parabolic"] = "uniform"


class SpallConfig(_Model):
    """Rectangular spall (Thibault et al. 2024, eq 13)."""

    gear: Literal["a", "b"] = "b"
    tooth: StrictInt = Field(0, ge=0)
    radius_m: float = Field(gt=0, description="radial centre of the spall (m)")
    radial_width_m: float = Field(gt=0, description="radial width d_r (m)")
    depth_m: float = Field(1e-4, gt=0, description="depth δ_spall (m)")
    axial_position_m: float | None = Field(
        None, ge=0, description="axial centre (m from face start)"
    )
    axial_length_m: float | None = Field(None, gt=0, description="axial length d_z (m)")


class TipReliefConfig(_Model):
    gear: Literal["a", "b"] = "a"
    amount_m: float = Field(gt=0, description="relief at the tip (m)")
    start_radius_m: float = Field(gt=0, description="radius where the relief starts (m)")
    shape: Literal["linear", "parabolic"] = "linear"


class GearGeometryConfig(_Model):
    """Geometry of a named gear pair (or of all planets' sun or ring meshes of a stage)."""

    pair: str = Field(min_length=1, description="gear pair / stage / planetary mesh name")
    normal_module_m: float = Field(
        gt=0, le=0.1, description="normal module m_n (m; a module over 0.1 m is refused: a value "
        "in mm typed into this m field)")
    normal_pressure_angle_deg: float = Field(20.0, gt=0, lt=45, description="α_n (deg)")
    helix_angle_deg: float = Field(0.0, gt=-60, lt=60, description="β (deg)")
    face_width_m: float = Field(gt=0, description="face width b (m)")
    a: WheelGeometry = Field(default_factory=WheelGeometry)
    b: WheelGeometry = Field(default_factory=WheelGeometry)
    cracks: list[CrackConfig] = Field(default_factory=list)
    spalls: list[SpallConfig] = Field(default_factory=list)
    tip_reliefs: list[TipReliefConfig] = Field(default_factory=list)
    lead_crowning_m: float = Field(0.0, ge=0, description="lead crowning at the face ends (m)")
    profile_crowning_m: float = Field(
        0.0, ge=0, description="profile crowning at the ends of the path of contact (m)"
    )
    torque_nm: float | None = Field(
        None, gt=0, description="torque on the pinion (N·m) for loaded-contact analysis"
    )
    slice_coupling: bool = Field(
        False, description="couple the face slices of each tooth in the mesh stiffness tables "
        "(Thibault et al. 2024, §2.2 unloaded-slice correction: two-parameter foundation, a "
        "partly loaded "
        "face is stiffer than its loaded slices alone); false = independent slices")
    slice_coupling_length_ratio: float | None = Field(
        None, gt=0, le=5, description="decay length of the slice coupling over the load height "
        "λ/h (dimensionless; default √(0.8 − ν) from the cantilever-plate derivation); needs "
        "slice_coupling = true")


def matches(entry: str, mesh_name: str, stage: str | None) -> bool:
    """Whether the ``pair`` name of an entry designates the mesh ``mesh_name`` (of planetary
    stage ``stage``): the mesh's own name, or ``'<stage>.sun-planet'`` /
    ``'<stage>.ring-planet'`` for every planet of the stage."""
    if entry == mesh_name:
        return True
    if stage is not None and mesh_name.startswith(entry):
        rest = mesh_name[len(entry) :]
        return entry in (f"{stage}.sun-planet", f"{stage}.ring-planet") and rest.isdigit()
    return False


_matches = matches  # the name used before the builder moved out


def mechanism_meshes(cfg):  # noqa: ANN001, ANN202
    """The meshes of the config's mechanism graph and the names of its bevel stages."""
    from geardyn.config.mechanism import BevelStage

    bevel = {st.name for st in cfg.bevel if isinstance(st, BevelStage)}
    return [m for m in cfg.graph().meshes], bevel


def check_gear_geometry(cfg) -> list[str]:  # noqa: ANN001
    """Problems of the ``gear_geometry`` section (one message per problem, naming the entry)."""
    problems: list[str] = []
    if not cfg.gear_geometry:
        return problems
    meshes, bevel = mechanism_meshes(cfg)
    seen: dict[str, int] = {}
    for i, entry in enumerate(cfg.gear_geometry):
        where = f"gear_geometry[{i}] (pair '{entry.pair}')"
        if entry.pair in bevel:
            problems.append(f"{where}: bevel stages are not supported (cylindrical gears only)")
            continue
        matched = [m for m in meshes if matches(entry.pair, m.name, m.stage)]
        if not matched:
            names = ", ".join(m.name for m in meshes)
            problems.append(f"{where}: no gear pair of that name (known: {names})")
            continue
        for m in matched:
            if m.name in seen:
                problems.append(
                    f"{where}: pair '{m.name}' already has geometry (gear_geometry[{seen[m.name]}])"
                )
            seen[m.name] = i
        from geardyn.models.gear_pairs import build_pair  # the builder checks what it builds

        try:
            build_pair(entry, matched[0], matched[0].name)
        except ConfigError as exc:
            problems.extend(f"gear_geometry[{i}]: {p}" for p in exc.problems)
    return problems


#: Names that moved to the builder :mod:`geardyn.models.gear_pairs` (the config layer
#: describes, the builder builds); reached here only by old imports, resolved on first use.
_MOVED = ("PairModel", "pair_model", "pair_names")


def __getattr__(name: str):  # noqa: ANN202 - module attribute hook (PEP 562)
    if name in _MOVED:
        from geardyn.models import gear_pairs

        return getattr(gear_pairs, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
