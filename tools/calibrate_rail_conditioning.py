"""Calibrate the rail cells' reference energy of a conditioned adhesion preset (heavy-rain).

Run: python tools/calibrate_rail_conditioning.py [condition]. For each reference energy of a
logarithmic scan it runs the preset's calibration stop (conditioning.cells.calibration_scenario)
with the rail cleaned cell by cell, measures each car's maximum adhesion as the file says
(railbrake.adhesion.car_max_adhesion above calibration_above_kmh) and prints the sum of squared
relative errors against the file's car-by-car targets; the least is written into the file by hand.
The targets are checked by tests/unit/simulation/test_rail_conditioning.py.
"""

import sys
import tempfile
from importlib import resources
from pathlib import Path

import numpy as np

from railbrake import simulation
from railbrake.adhesion import car_max_adhesion, load_condition
from railbrake.scenario import load


def measure(name: str, reference_energy: float) -> dict:
    """Each car's maximum adhesion in the preset's calibration stop at this reference energy."""
    k = load_condition(name).conditioning
    preset = Path(str(resources.files("railbrake") / "data" / "adhesion" / f"{name}.yaml"))
    text = preset.read_text().replace(f"reference_energy_J_m2: {k.reference_energy:g}",
                                      f"reference_energy_J_m2: {reference_energy:g}")
    path = Path(tempfile.mkdtemp()) / f"{name}.yaml"
    path.write_text(text)
    scenario = load(k.calibration_scenario).with_({"adhesion.condition": str(path), "adhesion.rail_conditioning": "cells"})
    return car_max_adhesion(simulation.run(scenario), k.calibration_above_kmh)


def main(name: str = "heavy-rain") -> None:
    condition = load_condition(name)
    targets = [t for t in condition.targets if t.get("car")]
    best = None
    for energy in np.arange(3000.0, 12001.0, 500.0):   # J/m2 (the error is flat to a few hundred)
        cars = measure(name, float(energy))
        error = sum((cars[t["car"]] / t["peak"] - 1.0) ** 2 for t in targets)
        print(f"reference_energy {energy:8.0f} J/m2: " + ", ".join(
            f"car {t['car']} {cars[t['car']]:.4f} (target {t['peak']})" for t in targets) + f", error {error:.4f}")
        best = min(best or (error, energy), (error, energy))
    print(f"least error at reference_energy {best[1]:.0f} J/m2")


if __name__ == "__main__":
    main(*sys.argv[1:])
