"""Coaxial planetary stages in series keep one central axis whatever the declaration order
(issue 11, item 1): the sun of one stage is the carrier of the next, then a parallel stage."""

from __future__ import annotations

import itertools

import pytest

from geardyn import analyze_kinematics
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError

#: (name, sun, carrier, z_sun, z_planet, z_ring); ring fixed in the housing
STAGES = [
    ("st1", "s1", "rotor", 21, 39, 99),
    ("st2", "s2", "s1", 24, 36, 96),
    ("st3", "s3", "s2", 30, 33, 96),
]


def _config(order: tuple[int, ...], n_stages: int, swap_parallel: bool = False) -> dict:
    stages = STAGES[:n_stages]
    last = stages[-1][1]
    sides = [dict(link=last, teeth=87), dict(link="out", teeth=23)]
    if swap_parallel:
        sides.reverse()
    return dict(
        frame="housing",
        links=["housing", "rotor", *[s[1] for s in stages], "out"],
        planetary=[
            dict(name=n, sun=s, ring="housing", carrier=c, sun_teeth=zs, planet_teeth=zp,
                 ring_teeth=zr, n_planets=3)
            for n, s, c, zs, zp, zr in (stages[i] for i in order)
        ],
        parallel=[dict(name="p3", a=sides[0], b=sides[1])],
        input_speeds_rpm={"rotor": 15.0},
    )


def _ratios(d: dict) -> dict[str, complex]:
    kin = analyze_kinematics(parse_config(d))
    assert kin.dof == 1
    om = kin.velocity_ratios(["rotor"])[:, 0]
    return dict(zip(kin.links, om, strict=True))


def _expected(n_stages: int) -> dict[str, float]:
    """Fixed-ring stage: ω_s/ω_c = 1 + z_r/z_s; parallel external pair: −z_a/z_b."""
    out = {"rotor": 1.0}
    w = 1.0
    for _n, s, _c, zs, _zp, zr in STAGES[:n_stages]:
        w *= 1 + zr / zs
        out[s] = w
    out["out"] = -w * 87 / 23
    return out


@pytest.mark.parametrize("n_stages", [2, 3])
def test_every_declaration_order_gives_the_same_kinematics(n_stages):
    want = _expected(n_stages)
    for order in itertools.permutations(range(n_stages)):
        for swap in (False, True):
            got = _ratios(_config(order, n_stages, swap))
            for link, w in want.items():
                assert got[link] == pytest.approx(w, rel=1e-12), (order, swap, link)


def test_shared_shaft_has_one_axis_in_both_orders():
    for order in ((0, 1), (1, 0)):
        g = parse_config(_config(order, 2)).graph()
        axes = {j.axis for j in g.joints if "housing" in (j.link_a, j.link_b)
                and {j.link_a, j.link_b} & {"rotor", "s1", "s2"}}
        assert len(axes) == 1, (order, axes)


def test_two_explicit_axis_levels_still_conflict():
    d = _config((0, 1), 2)
    d["turning_pairs"] = [dict(links=["s1", "housing"], axis="A")]
    d["planetary"][1]["axis"] = "B"
    with pytest.raises(ConfigError, match="already turns in 'housing' about axis"):
        parse_config(d)


def test_parallel_pair_made_coaxial_is_refused():
    d = _config((0, 1), 2)
    d["parallel"] = [dict(name="bad", a=dict(link="s1", teeth=30), b=dict(link="s2", teeth=20))]
    with pytest.raises(ConfigError, match="turn about the same axis"):
        parse_config(d)



def test_the_dynamic_model_does_not_depend_on_the_declaration_order(examples_dir):
    """The three-stage gearbox example with its planetary stages and the parallel sides
    declared in other orders has the same natural frequencies (and rigid mode count)."""
    import tomllib

    import scipy.linalg as sla

    from geardyn.models.core import model_from_config

    base = tomllib.loads((examples_dir / "three_stage_gearbox.toml").read_text())

    def freqs(d: dict) -> list[float]:
        m = model_from_config(parse_config(d))
        w2 = sla.eigh(m.stiffness_matrix(), m.M, eigvals_only=True)
        return sorted(float(x) for x in w2)

    want = freqs(base)
    swapped = dict(base, planetary=base["planetary"][::-1])
    par = dict(base["parallel"][0])
    par["a"], par["b"] = par["b"], par["a"]
    both = dict(swapped, parallel=[par])
    for d in (swapped, both):
        got = freqs(d)
        assert got[0] == pytest.approx(0.0, abs=1e-9 * want[-1])
        assert got[1:] == pytest.approx(want[1:], rel=1e-10)
