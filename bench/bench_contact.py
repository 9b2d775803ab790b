"""Creep-force evaluations per second: inside C (one call over a large array), through the
vectorised Python call on small arrays (binding overhead included), and scalar calls."""

import time

import numpy as np

from railbrake.contact import PolachParams, default_contact, polach_coefficient, polach_peak


def rate(function, evaluations, repeat=3):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return evaluations / best


def main():
    contact = default_contact()
    params = PolachParams(0.55, 0.4, 0.6, 1.0, 0.4)
    q = contact.normal_force
    big = np.linspace(-1.0, 1.0, 1_000_000)
    small = np.linspace(-0.3, 0.3, 100)
    c_rate = rate(lambda: polach_coefficient(big, 50.0, q, contact, params), big.size)
    vec_rate = rate(lambda: [polach_coefficient(small, 50.0, q, contact, params) for _ in range(2000)],
                    2000 * small.size)
    scalar_rate = rate(lambda: [polach_coefficient(0.01, 50.0, q, contact, params) for _ in range(20000)], 20000)
    peak_rate = rate(lambda: [polach_peak(50.0, q, contact, params) for _ in range(2000)], 2000)
    print(f"Polach F/Q in C (1e6-point array, one call): {c_rate / 1e6:8.1f} M evaluations/s")
    print(f"Polach F/Q via Python, 100-point arrays:     {vec_rate / 1e6:8.2f} M evaluations/s")
    print(f"Polach F/Q via Python, scalar calls:         {scalar_rate / 1e3:8.1f} k evaluations/s")
    print(f"peak adhesion search (C):                    {peak_rate / 1e3:8.1f} k searches/s")


if __name__ == "__main__":
    main()
