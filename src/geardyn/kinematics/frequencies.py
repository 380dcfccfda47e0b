"""Characteristic frequencies of a geared mechanism for given input speeds.

From the link angular velocities of seed 000 eq 5 (complex, rad/s):

- link speed ``|ω_i|`` (rpm, Hz) and direction ``arg ω_i`` (seed 000 §2.5); the signed speed
  about the link's own axis ``Re(e^{−iφ_i} ω_i)`` (axis direction ``φ_i``, NaN when the link's
  rotation is not along its own axis: :mod:`geardyn.kinematics.willis`);
- mesh frequency of gear pair (i, j) with carrier k: ``f_m = N_i·|ω_i − ω_k|/2π``
  (= ``N_j·|ω_j − ω_k|/2π`` by Willis, seed 000 eq 2; seed 003 eq 1.2 for fixed axes);
- tooth-fault frequency of a wheel: one impact per revolution relative to the carrier of each
  mesh it takes part in, summed over its meshes (a sun meshing with n planets gives
  ``n·(f_s − f_c)``, seed 003 notes §2.1);
- hunting-tooth frequency ``f_m / lcm(N_i, N_j)`` (the same tooth pair meets again);
- planet-pass frequency ``n·|ω_c − ω_r|/2π`` for n planets on carrier c meshing ring r;
- bearing FTF/BPFO/BPFI/BSF from the speeds of the two rings (:mod:`geardyn.bearings`).

Orders are frequencies divided by the rotation frequency of a reference link (default: the
first input).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from geardyn.bearings.frequencies import bearing_frequencies
from geardyn.errors import InputError
from geardyn.kinematics.willis import KinematicAnalysis

if TYPE_CHECKING:  # imported where used: pandas costs ~0.6 s and most commands never need it
    import pandas as pd
    import xarray as xr

RPM_TO_RAD_S = 2.0 * math.pi / 60.0
TWO_PI = 2.0 * math.pi


@dataclass
class CharacteristicFrequencies:
    """All characteristic frequencies of a mechanism at one operating point.

    Tables (pandas DataFrames, frequencies in Hz, speeds in rpm, angles in degrees):
    ``links``, ``meshes``, ``wheels``, ``bearings``, ``planet_pass``.
    """

    mechanism: str
    dof: int
    inputs_rpm: dict[str, float]
    order_reference: str
    reference_hz: float
    links: pd.DataFrame
    meshes: pd.DataFrame
    wheels: pd.DataFrame
    bearings: pd.DataFrame
    planet_pass: pd.DataFrame
    notes: list[str] = field(default_factory=list)

    TABLES = ("links", "meshes", "wheels", "bearings", "planet_pass")

    def to_dict(self) -> dict:
        """Plain-Python dictionary (JSON-serialisable)."""
        out = {
            "mechanism": self.mechanism,
            "dof": self.dof,
            "inputs_rpm": self.inputs_rpm,
            "order_reference": self.order_reference,
            "reference_hz": self.reference_hz,
        }
        for name in self.TABLES:
            df: pd.DataFrame = getattr(self, name)
            out[name] = json.loads(df.to_json(orient="records"))
        out["notes"] = list(self.notes)
        return out

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent, ensure_ascii=False)

    def to_xarray(self) -> xr.Dataset:
        """One dataset with dims ``link``, ``mesh``, ``wheel``, ``bearing``, ``planet_set``."""
        import xarray as xr

        dims = {
            "links": "link",
            "meshes": "mesh",
            "wheels": "wheel",
            "bearings": "bearing",
            "planet_pass": "planet_set",
        }
        parts = []
        for table, dim in dims.items():
            df: pd.DataFrame = getattr(self, table)
            if df.empty:
                continue
            key = df.columns[0]
            d = df.set_index(key)
            d.index.name = dim
            ds = xr.Dataset.from_dataframe(d)
            ds = ds.rename({c: f"{dim}_{c}" for c in d.columns if c in ds.data_vars})
            parts.append(ds)
        ds = xr.merge(parts, compat="no_conflicts", join="outer") if parts else xr.Dataset()
        ds.attrs.update(
            mechanism=self.mechanism,
            dof=self.dof,
            order_reference=self.order_reference,
            reference_hz=self.reference_hz,
            units="frequencies in Hz, speeds in rpm, angles in degrees, orders per rev of the "
            "order reference",
            inputs_rpm=json.dumps(self.inputs_rpm),
        )
        return ds


def link_speeds(
    analysis: KinematicAnalysis, input_speeds_rpm: Mapping[str, float | np.ndarray]
) -> np.ndarray:
    """Complex absolute angular velocities of all links (rad/s) for input speeds in rpm."""
    rad = {k: np.asarray(v, dtype=float) * RPM_TO_RAD_S for k, v in input_speeds_rpm.items()}
    return analysis.speeds(rad)


def mesh_frequencies(analysis: KinematicAnalysis, omega: np.ndarray) -> np.ndarray:
    """Mesh frequency (Hz) of every gear pair, ``N_a·|ω_a − ω_k|/2π`` (seed 000 eq 2).

    ``omega`` is the output of :func:`link_speeds`; the result has shape
    ``(n_meshes, *omega.shape[1:])``.
    """
    g = analysis.graph
    out = []
    for mesh, k in zip(g.meshes, analysis.carriers, strict=True):
        rel = omega[g.index(mesh.link_a)] - omega[g.index(k)]
        out.append(mesh.teeth_a * np.abs(rel) / TWO_PI)
    return np.array(out)


def _polar(z: complex) -> str:
    mag, ang = abs(z), math.degrees(math.atan2(z.imag, z.real)) if abs(z) > 0 else 0.0
    if abs(ang) < 1e-9:
        return f"{mag:.6g}"
    if abs(abs(ang) - 180.0) < 1e-9:
        return f"{-mag:.6g}"
    return f"{mag:.6g}∠{ang:.4g}°"


def characteristic_frequencies(
    analysis: KinematicAnalysis,
    input_speeds_rpm: Mapping[str, float],
    order_reference: str | None = None,
) -> CharacteristicFrequencies:
    """Characteristic frequencies at constant input speeds (rpm, signed).

    ``order_reference`` names the link whose rotation frequency defines order 1 (default: the
    first input link).
    """
    import pandas as pd

    if not input_speeds_rpm:
        raise InputError(
            f"no input speeds given: the mechanism has {analysis.dof} DOF; give "
            f"{analysis.dof} input link speed(s) in rpm (e.g. --input LINK=RPM)"
        )
    inputs = {k: float(v) for k, v in input_speeds_rpm.items()}
    g = analysis.graph
    omega = link_speeds(analysis, inputs)  # rad/s, complex
    ratios = analysis.velocity_ratios(list(inputs))
    ref = order_reference or next(iter(inputs))
    if ref not in g.links:
        raise InputError(f"order reference '{ref}': unknown link")
    f_ref = abs(omega[g.index(ref)]) / TWO_PI
    notes: list[str] = []
    if f_ref == 0:
        notes.append(f"order reference '{ref}' is at rest: orders are not defined (NaN)")

    def order(f: float) -> float:
        return f / f_ref if f_ref > 0 else float("nan")

    # links
    rows = []
    for i, name in enumerate(g.links):
        w = complex(omega[i])
        rows.append(
            {
                "link": name,
                "rpm": abs(w) / RPM_TO_RAD_S,
                "signed_rpm": analysis.signed_speed(name, w) / RPM_TO_RAD_S,
                "axis_deg": math.degrees(analysis.axes[name]),
                "hz": abs(w) / TWO_PI,
                "direction_deg": math.degrees(math.atan2(w.imag, w.real)) if abs(w) > 0 else 0.0,
                "order": order(abs(w) / TWO_PI),
                "ratio": " | ".join(_polar(complex(r)) for r in ratios[i]),
            }
        )
    links = pd.DataFrame(rows)

    # meshes
    fm = mesh_frequencies(analysis, omega)
    rows = []
    for mesh, k, f in zip(g.meshes, analysis.carriers, fm, strict=True):
        lcm = math.lcm(mesh.teeth_a, mesh.teeth_b)
        rel_a = abs(omega[g.index(mesh.link_a)] - omega[g.index(k)]) / TWO_PI
        rel_b = abs(omega[g.index(mesh.link_b)] - omega[g.index(k)]) / TWO_PI
        rows.append(
            {
                "pair": mesh.name,
                "link_a": mesh.link_a,
                "link_b": mesh.link_b,
                "carrier": k,
                "teeth_a": mesh.teeth_a,
                "teeth_b": mesh.teeth_b,
                "mesh_hz": float(f),
                "mesh_order": order(float(f)),
                "rel_a_hz": float(rel_a),
                "rel_b_hz": float(rel_b),
                "hunting_hz": float(f) / lcm,
                "hunting_period_s": lcm / float(f) if f > 0 else float("inf"),
            }
        )
    meshes = pd.DataFrame(rows)

    # wheels: a tooth fault on a wheel strikes once per relative revolution in every mesh
    wheel_rows: dict[str, dict] = {}
    for mesh, k in zip(g.meshes, analysis.carriers, strict=True):
        for link, wheel, teeth, other in (
            (mesh.link_a, mesh.wheel_a, mesh.teeth_a, mesh.link_b),
            (mesh.link_b, mesh.wheel_b, mesh.teeth_b, mesh.link_a),
        ):
            rel = abs(omega[g.index(link)] - omega[g.index(k)]) / TWO_PI
            key = wheel or f"{link}/z{teeth}"
            row = wheel_rows.setdefault(
                key,
                {"wheel": key, "link": link, "teeth": teeth, "meshes_with": [], "fault_hz": 0.0},
            )
            row["meshes_with"].append(other)
            row["fault_hz"] += float(rel)
    for row in wheel_rows.values():
        row["n_meshes"] = len(row["meshes_with"])
        row["meshes_with"] = ", ".join(row["meshes_with"])
        row["fault_order"] = order(row["fault_hz"])
    wheels = pd.DataFrame(list(wheel_rows.values()))
    if not wheels.empty:
        wheels = wheels[
            ["wheel", "link", "teeth", "n_meshes", "meshes_with", "fault_hz", "fault_order"]
        ]

    # bearings
    rows = []
    for b in g.bearings:
        wi, wo = omega[g.index(b.inner)], omega[g.index(b.outer)]
        rel = abs(wi - wo) / TWO_PI
        bf = bearing_frequencies(
            rel, 0.0, b.n_elements, b.element_diameter, b.pitch_diameter, b.contact_angle
        )
        gamma = b.element_diameter / b.pitch_diameter * math.cos(b.contact_angle)
        cage_abs = abs(wo + 0.5 * (wi - wo) * (1 - gamma)) / TWO_PI
        rows.append(
            {
                "bearing": b.name,
                "inner": b.inner,
                "outer": b.outer,
                "kind": b.kind,
                "rel_hz": float(rel),
                "ftf_hz": bf.ftf,
                "cage_abs_hz": float(cage_abs),
                "bpfo_hz": bf.bpfo,
                "bpfi_hz": bf.bpfi,
                "bsf_hz": bf.bsf,
                "ball_fault_hz": 2.0 * bf.bsf,
                "bpfo_order": order(bf.bpfo),
                "bpfi_order": order(bf.bpfi),
                "bsf_order": order(bf.bsf),
                "ftf_order": order(bf.ftf),
            }
        )
    bearings = pd.DataFrame(rows)

    # planet pass: planets on a moving carrier meshing one internal/central wheel
    rows = []
    for carrier, central, wheel, planets in planet_groups(analysis):
        f_pp = len(planets) * abs(omega[g.index(carrier)] - omega[g.index(central)]) / TWO_PI
        rows.append(
            {
                "set": f"{wheel}@{carrier}",
                "central": central,
                "carrier": carrier,
                "n_planets": len(planets),
                "planet_pass_hz": float(f_pp),
                "planet_pass_order": order(float(f_pp)),
            }
        )
    planet_pass = pd.DataFrame(rows)
    return CharacteristicFrequencies(
        mechanism=g.name,
        dof=analysis.dof,
        inputs_rpm=inputs,
        order_reference=ref,
        reference_hz=float(f_ref),
        links=links,
        meshes=meshes,
        wheels=wheels,
        bearings=bearings,
        planet_pass=planet_pass,
        notes=notes,
    )


def planet_groups(analysis: KinematicAnalysis) -> list[tuple[str, str, str, list[str]]]:
    """Groups ``(carrier, central link, central wheel, planets)`` for planet-pass frequencies.

    A planet is a link held only by its carrier (its turning pairs all join the carrier) that
    meshes with a central wheel (on a link not held only by the carrier); the carrier must not
    be the frame. Groups are per central wheel, so the sun and the ring of a stage give two
    entries (planet pass relative to the sun and to the ring), and two stages sharing a sun
    shaft stay separate.
    """
    g = analysis.graph
    holders: dict[str, set[str]] = {}
    for jt in g.joints:
        holders.setdefault(jt.link_a, set()).add(jt.link_b)
        holders.setdefault(jt.link_b, set()).add(jt.link_a)
    groups: dict[tuple[str, str, str], list[str]] = {}
    for mesh, k in zip(g.meshes, analysis.carriers, strict=True):
        if k == g.frame:
            continue
        sides = (
            (mesh.link_a, mesh.link_b, mesh.wheel_b or f"{mesh.link_b}/z{mesh.teeth_b}"),
            (mesh.link_b, mesh.link_a, mesh.wheel_a or f"{mesh.link_a}/z{mesh.teeth_a}"),
        )
        for planet, central, wheel in sides:
            if holders.get(planet, set()) == {k} and holders.get(central, set()) != {k}:
                lst = groups.setdefault((k, central, wheel), [])
                if planet not in lst:
                    lst.append(planet)
    return [(k, c, w, p) for (k, c, w), p in groups.items()]


def frequency_tracks(
    analysis: KinematicAnalysis,
    input_speeds_rpm: Mapping[str, np.ndarray],
    time: np.ndarray | None = None,
) -> xr.Dataset:
    """Characteristic frequencies along a speed profile (run-up, run-down, variable speed).

    ``input_speeds_rpm`` maps each input link to an array of speeds (rpm, signed, one value per
    sample of ``time`` in s; all arrays of one length). Returns a dataset with dims
    ``link``/``mesh``/``bearing`` × ``time``: ``link_hz`` (rotation frequency), ``mesh_hz``
    (seed 000 eq 2 with the carrier of each pair), ``bpfo_hz``, ``bpfi_hz``, ``bsf_hz``,
    ``ftf_hz``. Orders do not change along the profile (kinematic ratios are constant), so
    they are given by :func:`characteristic_frequencies`.
    """
    import xarray as xr

    arrays = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in input_speeds_rpm.items()}
    lengths = {v.shape for v in arrays.values()}
    if len(lengths) != 1 or len(next(iter(lengths))) != 1:
        raise InputError(
            f"input_speeds_rpm: all speed profiles must be 1-D arrays of one length (got shapes "
            f"{ {k: v.shape for k, v in arrays.items()} })"
        )
    n = next(iter(arrays.values())).shape[0]
    if time is None:
        time = np.arange(n, dtype=float)
    time = np.asarray(time, dtype=float)
    if time.shape != (n,):
        raise InputError(f"time: must have one value per speed sample ({n}), got {time.shape}")
    g = analysis.graph
    omega = link_speeds(analysis, arrays)  # (N, n) complex rad/s
    data: dict[str, tuple] = {
        "link_hz": (("link", "time"), np.abs(omega) / TWO_PI, {"units": "Hz"}),
        "mesh_hz": (("mesh", "time"), mesh_frequencies(analysis, omega), {"units": "Hz"}),
    }
    coords: dict[str, object] = {
        "time": ("time", time, {"units": "s"}),
        "link": g.links,
        "mesh": [m.name for m in g.meshes],
    }
    if g.bearings:
        cols: dict[str, list[np.ndarray]] = {"ftf": [], "bpfo": [], "bpfi": [], "bsf": []}
        for b in g.bearings:
            rel = np.abs(omega[g.index(b.inner)] - omega[g.index(b.outer)]) / TWO_PI
            bf = bearing_frequencies(
                rel, 0.0, b.n_elements, b.element_diameter, b.pitch_diameter, b.contact_angle
            )
            for k in cols:
                cols[k].append(np.asarray(getattr(bf, k)))
        for k, v in cols.items():
            data[f"{k}_hz"] = (("bearing", "time"), np.array(v), {"units": "Hz"})
        coords["bearing"] = [b.name for b in g.bearings]
    return xr.Dataset(data, coords=coords, attrs={"mechanism": g.name})
