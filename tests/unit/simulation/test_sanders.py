"""Sanders of a train file (core/src/rail_conditioning.c) in runs: on heavy rain with the rail cells,
a WSP-triggered sander in front of the leading axle shortens the stop and books its sand; without
the rail cells the run says the sanders act on nothing."""

from importlib import resources

import pytest

from railbrake import simulation
from railbrake.scenario import load

SANDERS = """
sanders:
  units:
    - {car: 1, axle: 1, rate_kg_min: 1.5, trigger: wsp}
  sand_reference_kg_m: 0.002
  source: test values
"""


@pytest.fixture(scope="module")
def sanded_train(tmp_path_factory):
    text = (resources.files("railbrake") / "data" / "trains" / "crh380al-16.yaml").read_text()
    path = tmp_path_factory.mktemp("train") / "sanded.yaml"
    path.write_text(text + SANDERS)
    return str(path)


def _run(train=None, **changes):
    sc = load("emergency-300-heavy-rain").with_({"train.cars": 4, **({"train.preset": train} if train else {}),
                                                 **changes})
    return simulation.run(sc)


def test_sand_shortens_the_stop_on_heavy_rain(sanded_train):
    cells = {"adhesion.rail_conditioning": "cells"}
    plain, sanded = _run(**cells), _run(sanded_train, **cells)
    assert sanded.kpis["stopping_distance_m"] < 0.97 * plain.kpis["stopping_distance_m"]


def test_sanders_without_rail_cells_are_said_to_act_on_nothing(sanded_train):
    with pytest.warns(UserWarning, match="sanders act on the rail cells"):
        _run(sanded_train)
