"""The method against a brute-force Monte Carlo of whole-train stops (issue 26): at EBCL 90 % and
99 % its Kdry_rst lies within the 95 % interval of the brute-force quantile of 2000 stops, whose
failures and tolerances are drawn together.

A short, cheap configuration so that it fits the test budget: the first 2 cars of the CRH380A from
80 km/h, the shipped scatter file, and an EP valve lost with probability 2e-3 per car and demand
(far above the shipped file's, so that the failure states reach into the 99 % level)."""

import pytest

from railbrake.etcs import bruteforce, confidence, model

RELIABILITY = """schema: railbrake.reliability/1
name: test
source: test
failures:
  - {kind: ep_valve_failed, unit: car, per_demand: 2.0e-3, source: test}
"""


@pytest.mark.slow
def test_method_within_the_brute_force_interval_at_90_and_99_percent(tmp_path):
    path = tmp_path / "rel.yaml"
    path.write_text(RELIABILITY)
    spec = model.spec("crh380a-8", reliability=path, cars=2, initial_speed_kmh=80, samples=2048, rare_samples=256)
    method = model.braking_model(spec, workers=2)
    stops = bruteforce.ratios(spec, 2000, seed=20261204)
    for level in (1, 2):   # M_NVEBCL 1 and 2: 90 % and 99 %
        for j, step in enumerate(method.kdry):
            estimate, low, high = bruteforce.quantile_interval(stops[:, j], 1.0 - confidence.EBCL[level])
            print(f"EBCL {confidence.EBCL[level]:.0%}, step {j}: method {step[level]:.4f}, "
                  f"brute force {estimate:.4f} [{low:.4f}, {high:.4f}]")
            assert low <= step[level] <= high
