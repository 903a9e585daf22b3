"""Goodness-of-fit figures for frequency responses."""

from __future__ import annotations

import numpy as np


def fit_percent(H, H_model) -> float:
    """NRMSE fit as system-identification tools report it: 100 (1 - |H - Ĥ| / |H - mean H|) [%]."""
    H, h = np.asarray(H), np.asarray(H_model)
    return float(100.0 * (1.0 - np.linalg.norm(H - h) / np.linalg.norm(H - np.mean(H))))


def rel_error(H, H_model) -> float:
    """RMS relative complex error ``sqrt(mean |Ĥ/H - 1|^2)`` [-]."""
    return float(np.sqrt(np.mean(np.abs(np.asarray(H_model) / np.asarray(H) - 1.0) ** 2)))
