"""The table of adhesion conditions against the measured data sets (docs/validation.md)."""

from railbrake.adhesion import load_condition
from railbrake.validation.adhesion_table import OUTSIDE, condition_table, data_sets, residual


def _case(name):
    return next(c for c in data_sets() if c.id == name)


def test_a_condition_is_judged_only_inside_its_validity():
    # wet holds to 120 km/h; the design curve's points of wet-polach-at-300 lie at 250 and 300
    assert residual(load_condition("wet"), _case("wet-polach-at-300")) == OUTSIDE
    # hs-wet is fitted to the design curve 13.6/(v + 85) within 6 % (its file's source)
    assert abs(residual(load_condition("hs-wet"), _case("hs-wet-design-adhesion"))) < 0.06


def test_the_table_holds_every_condition_against_every_data_set():
    table = condition_table()
    sets = {c.id for c in data_sets()}
    assert {"curtius-kniffler-dry", "hs-wet-design-adhesion", "heavy-rain-front-car-300"} <= sets
    for name, row in table.items():
        assert set(row) == sets, name
        assert all(v == OUTSIDE or isinstance(v, float) for v in row.values())
    # dry-medium is fitted on the Curtius-Kniffler curve (within 4 %); Polach's dry set lies far above it
    assert abs(table["dry-medium"]["curtius-kniffler-dry"]) < 0.04
    assert table["dry-high"]["curtius-kniffler-dry"] > 0.3


def test_the_fit_table_gives_each_condition_its_data_sets_with_residuals_or_the_search():
    from railbrake.validation.adhesion_table import fit_table
    rows = fit_table()
    assert set(rows) == {c.name for c in __import__("railbrake").adhesion.conditions()}
    # dry-medium: fitted on Curtius-Kniffler (worst 4 %), checked on the clean-steel rig (far below its 0.5)
    assert rows["dry-medium"]["fitted on"].startswith("curtius-kniffler-dry (mean +0 %, worst -4 %)")
    assert "dry-br-rig (mean -50" in rows["dry-medium"]["checked on"]
    assert rows["oil-film"]["fitted on"].startswith("no data set: no published adhesion value")
    assert rows["hs-wet"]["at a bound"].startswith("A: finding")
    assert rows["leaves-full-scale"]["speed km/h"] == "64-113"
