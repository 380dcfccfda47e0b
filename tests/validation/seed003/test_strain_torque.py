"""Seed 003 eqs 4.15-4.16: motor torque from the full-bridge strain of the sun shaft,
M_t = ½ ε G S_p, S_p = π d³/16, checked against Hooke's law in pure shear (an independent
derivation: gauge at 45° reads γ/2, four active arms indicate 2γ)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.sensors.strain import (
    bridge_strain_from_torque,
    polar_section_modulus,
    torque_from_bridge_strain,
)

G_STEEL = 80e9  # Pa (typical steel; the thesis gives neither G nor d, notes §5.1 item 12)


def test_section_modulus_closed_form():
    # eq 4.16 against J/(d/2) with J = π d⁴/32
    d = 0.04
    assert polar_section_modulus(d) == pytest.approx((math.pi * d**4 / 32) / (d / 2), rel=1e-14)


def test_rated_motor_torque_round_trip_hooke():
    """Seed 003 Table 2.3 motor: 15 kW at 1460 rpm → 98.1 N·m (notes §5.1 item 11). Shear
    stress τ = 16 T/(π d³), γ = τ/G, gauges at ±45° read ±γ/2, the full bridge indicates
    4·γ/2; eq 4.15 must give the torque back."""
    torque = 15e3 / (1460 * 2 * math.pi / 60)
    assert torque == pytest.approx(98.1, abs=0.05)
    d = 0.035
    gamma = 16 * torque / (math.pi * d**3) / G_STEEL
    eps_bridge = 4 * gamma / 2
    assert torque_from_bridge_strain(eps_bridge, G_STEEL, d) == pytest.approx(torque, rel=1e-12)
    assert bridge_strain_from_torque(torque, G_STEEL, d) == pytest.approx(eps_bridge, rel=1e-12)


def test_history_and_errors():
    eps = np.linspace(-1e-4, 1e-4, 5)
    t = torque_from_bridge_strain(eps, G_STEEL, 0.03)
    np.testing.assert_allclose(bridge_strain_from_torque(t, G_STEEL, 0.03), eps, rtol=1e-12)
    with pytest.raises(InputError, match="diameter_m"):
        torque_from_bridge_strain(1e-4, G_STEEL, 0.0)
    with pytest.raises(InputError, match="shear_modulus_pa"):
        torque_from_bridge_strain(1e-4, float("nan"), 0.03)
    with pytest.raises(InputError, match="strain"):
        torque_from_bridge_strain([1e-4, np.inf], G_STEEL, 0.03)
