"""Resource estimates before allocation (issue 20, geardyn.resources): the numbers in the
messages are the hand products (samples = rate × duration, 8 bytes each; steps = t_end / dt),
and the memory limit follows GEARDYN_MAX_MEMORY_GB."""

from __future__ import annotations

import pytest

from geardyn.resources import MAX_STEPS, bytes_problem, max_bytes, run_problems, steps_problem


def test_steps_estimate():
    assert steps_problem("dt_s", 0.02, 2e-5) is None  # 1000 steps
    msg = steps_problem("dt_s", 0.02, 1e-12)
    assert msg is not None and "2e+10 time steps" in msg and f"{MAX_STEPS:.0e}" in msg


def test_bytes_estimate_and_limit(monkeypatch):
    monkeypatch.delenv("GEARDYN_MAX_MEMORY_GB", raising=False)
    assert max_bytes() == 4 * 2**30
    n = 5e8 * 50.0  # 500 MHz for 50 s
    msg = bytes_problem("sensors[0].sample_rate_hz", n, "samples")
    assert msg is not None and "2.5e+10 values" in msg and "186 GiB" in msg
    monkeypatch.setenv("GEARDYN_MAX_MEMORY_GB", "200")
    assert max_bytes() == 200 * 2**30
    assert bytes_problem("sensors[0].sample_rate_hz", n, "samples") is None
    monkeypatch.setenv("GEARDYN_MAX_MEMORY_GB", "nonsense")
    assert max_bytes() == 4 * 2**30


def test_run_problems_of_a_config(examples_dir, monkeypatch):
    from geardyn.config.loader import load_config

    monkeypatch.delenv("GEARDYN_MAX_MEMORY_GB", raising=False)
    cfg = load_config(examples_dir / "seed004_diagnose_sun_crack.toml")
    assert run_problems(cfg) == []  # 50 s at 5 kHz: 250 000 samples
    problems = run_problems(cfg, t_end_s=1e6, t_end_name="--t-end")
    # 1e6 s / 1e-4 s = 1e10 steps; 5 kHz × 1e6 s = 5e9 samples = 37.3 GiB
    assert any("planetary_dynamics.simulation.dt_s" in p and "1e+10 time steps" in p
               for p in problems)
    assert any("ring_acc" in p and "5e+09 values" in p and "--t-end = 1e+06 s" in p
               for p in problems)


@pytest.mark.parametrize("revolutions", [1e12])
def test_fe_run_length(examples_dir, revolutions):
    from geardyn.config.loader import load_config

    cfg = load_config(examples_dir / "seed002_transmission.toml")
    assert run_problems(cfg) == []
    problems = run_problems(cfg, "transmission", revolutions=revolutions,
                            revolutions_name="--revolutions")
    assert problems and all(p.startswith("--revolutions") for p in problems)
