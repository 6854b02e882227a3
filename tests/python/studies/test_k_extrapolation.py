"""The k -> 0 extrapolation of the sinusoidal-forcing viscosity (examples/viscosity_two_routes.py):
nu(k) = nu0 + c k^2 by weighted least squares, checked on synthetic data with known truth."""

import numpy as np
import pytest

from openmmdpd_studies.transport.estimators import extrapolate_k_squared


def test_exact_data_gives_the_line_and_the_textbook_error():
    k = np.array([1.0, 0.5, 0.25])
    errors = np.array([0.02, 0.03, 0.05])
    fit = extrapolate_k_squared(k, 0.9 - 0.15 * k**2, errors)
    assert fit["nu0"] == pytest.approx(0.9, abs=1e-12)
    assert fit["c"] == pytest.approx(-0.15, abs=1e-12)
    assert fit["chi2"] == pytest.approx(0.0, abs=1e-20) and fit["dof"] == 1
    # closed form of the intercept's variance for a weighted straight line: S_xx / (S S_xx - S_x^2)
    w, x = 1 / errors**2, k**2
    expected = np.sqrt(np.sum(w * x * x) / (np.sum(w) * np.sum(w * x * x) - np.sum(w * x) ** 2))
    assert fit["nu0_error"] == pytest.approx(expected, rel=1e-12)


def test_noisy_samples_recover_nu0_and_its_error():
    rng = np.random.default_rng(7)
    k = 2 * np.pi / np.array([5.5, 11.0, 16.5])
    errors = np.array([0.01, 0.015, 0.02])
    nu0, c = 0.85, 0.08
    fits = [extrapolate_k_squared(k, nu0 + c * k**2 + rng.normal(0, errors), errors) for _ in range(4000)]
    estimates = np.array([f["nu0"] for f in fits])
    reported = fits[0]["nu0_error"]
    assert all(f["nu0_error"] == pytest.approx(reported) for f in fits)  # errors are absolute, not rescaled by chi2
    # unbiased, and the reported error is the scatter of the estimates (4000 samples: ~1 % and ~2 % tolerances)
    assert abs(estimates.mean() - nu0) < 4 * reported / np.sqrt(len(fits))
    assert estimates.std(ddof=1) == pytest.approx(reported, rel=0.05)
    coverage = np.mean(np.abs(estimates - nu0) <= 2 * reported)
    assert 0.94 < coverage < 0.97
    chi2 = np.array([f["chi2"] for f in fits])
    assert chi2.mean() == pytest.approx(1.0, rel=0.1)  # one degree of freedom


def test_bad_input_is_refused():
    with pytest.raises(ValueError):
        extrapolate_k_squared([1.0, 1.0], [0.9, 0.8], [0.1, 0.1])
    with pytest.raises(ValueError):
        extrapolate_k_squared([1.0, 0.5], [0.9, 0.8], [0.1, 0.0])
