"""Each adhesion condition's fit: the data sets it was fitted on and checked on (validation cases),
its parameters inside the fit's bounds, or at one with the finding that says which data disagree."""

from importlib import resources

import pytest

from railbrake import adhesion
from railbrake.adhesion.conditions import at_fit_bound
from railbrake.errors import InputError
from railbrake.validation.adhesion_table import OUTSIDE, data_sets, residual
from railbrake.validation.cases import load_cases
from railbrake.validation.runner import evaluate

SETS = {c.id: c for c in data_sets()}


def _preset_text(name):
    return (resources.files("railbrake") / "data" / "adhesion" / f"{name}.yaml").read_text()


@pytest.mark.parametrize("name", adhesion.preset_names())
def test_every_condition_names_its_data_sets_or_the_search_that_found_none(name):
    fit = adhesion.load_condition(name).fit
    assert fit is not None, f"{name}: no fit block"
    for case_id in fit.fitted_on + fit.checked_on:
        assert case_id in SETS, f"{name}: {case_id} is not an adhesion data set in validation/"
    assert fit.fitted_on or len(fit.no_data) > 80, f"{name}: neither a data set nor what was searched"
    assert not set(fit.fitted_on) & set(fit.checked_on), f"{name}: a data set both fitted and checked"
    assert fit.creep


@pytest.mark.parametrize("name", adhesion.preset_names())
def test_no_fitted_parameter_at_a_bound_without_the_finding(name):
    condition = adhesion.load_condition(name)
    values = condition.fit_values()
    for parameter, (low, high) in condition.fit.bounds.items():
        assert low <= values[parameter] <= high
        if at_fit_bound(values[parameter], low, high):
            finding = condition.fit.at_bound.get(parameter, "")
            assert "finding" in finding and "data" in finding, f"{name}.{parameter} at a bound: {finding!r}"


def test_the_parameter_at_a_bound_is_the_finding_known():
    """hs-wet's A left its bound with the rolling-speed factor (A, B now heavy-rain's, mu0 and v_ref
    fitted); heavy-rain's leading factor stays at its bound, with the factor too."""
    at_bound = {(c.name, p) for c in adhesion.conditions() for p in c.fit.at_bound}
    assert at_bound == {("heavy-rain", "leading_factor")}


@pytest.mark.parametrize("name", adhesion.preset_names())
def test_a_fitted_data_set_lies_inside_the_validity_it_gives(name):
    condition = adhesion.load_condition(name)
    for case_id in condition.fit.fitted_on:
        assert residual(condition, SETS[case_id]) != OUTSIDE, f"{name}: its own data set {case_id} is outside"


def test_the_leaf_scatter_is_two_presets_each_checked_on_the_others_data():
    leaves, rig = adhesion.load_condition("leaves"), adhesion.load_condition("leaves-full-scale")
    # each fits its own data (the rig: 0.01-0.02 at 64 and 113 km/h; leaf layers: 0.01-0.05)
    assert abs(residual(rig, SETS["leaves-full-scale-rig"])) < 0.05
    assert abs(residual(leaves, SETS["leaves-leaf-layer-friction"])) < 0.05
    # the rig preset lies inside the leaf-layer range (a check on other data); leaves lies 2x above the rig
    assert 0.01 <= adhesion.peak_adhesion(rig, 100 / 3.6).coefficient <= 0.05
    assert residual(leaves, SETS["leaves-full-scale-rig"]) > 0.8


def test_a_parameter_at_a_bound_without_a_finding_is_refused(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(_preset_text("heavy-rain").split("  at_bound:")[0] + "  creep: peaks only\n")
    with pytest.raises(InputError, match=r"fit\.parameters\.leading_factor: the value 0\.2 sits at a bound"):
        adhesion.load_condition(path)


def test_a_fit_without_data_or_search_is_refused(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(_preset_text("dry-medium").replace("fitted_on: [curtius-kniffler-dry]", "fitted_on: []"))
    with pytest.raises(InputError, match="fitted_on is empty"):
        adhesion.load_condition(path)


CASES = {c.id: c for c in load_cases(None, kind="validation")}


@pytest.mark.parametrize("case_id", ["curtius-kniffler-dry", "wet-polach-at-300", "heavy-rain-train-mean-design"])
def test_the_three_adhesion_cases_pass_or_are_findings_naming_the_data(case_id):
    result = evaluate(CASES[case_id])
    assert result.status in ("pass", "fail")
    if result.status == "fail":
        finding = CASES[case_id].expected_failure or ""
        assert "Shinkansen" in finding and ("Polach" in finding or "car" in finding), finding


def test_hs_wet_follows_the_design_curve_by_its_rolling_speed_factor():
    """hs-wet: heavy-rain's curve with mu0 / (1 + v / v_ref) fitted on the Shinkansen design curve
    (the data set hs-wet-design-adhesion, within 1 % on average, 2.3 % at worst) and checked on data
    not fitted, the heavy-rain band at 300 km/h (0.02 front car to 0.05 car 4); v_ref and mu0 inside
    their fit's bounds."""
    hs_wet, rain = adhesion.load_condition("hs-wet"), adhesion.load_condition("heavy-rain")
    assert (hs_wet.params.A, hs_wet.params.B, hs_wet.params.kA, hs_wet.params.kS) == \
        (rain.params.A, rain.params.B, rain.params.kA, rain.params.kS)
    values = hs_wet.fit_values()
    for name, (low, high) in hs_wet.fit.bounds.items():
        assert not at_fit_bound(values[name], low, high), name
    assert abs(residual(hs_wet, SETS["hs-wet-design-adhesion"])) < 0.01
    assert 0.02 <= adhesion.peak_adhesion(hs_wet, 300 / 3.6).coefficient <= 0.05


def test_a_file_without_the_rolling_speed_factor_has_none(tmp_path):
    """Absent, the factor is off: the condition's law is Polach's, the limit of the file with v_ref_kmh
    far beyond the train's speed (at 36000 km/h, 300 km/h lowers mu0 by 300/36000 = 0.8 %)."""
    text = _preset_text("hs-wet")
    path, far = tmp_path / "off.yaml", tmp_path / "far.yaml"
    path.write_text(text.replace(", v_ref_kmh: 152.4}", "}").split("fit:")[0])
    far.write_text(text.replace("v_ref_kmh: 152.4", "v_ref_kmh: 36000").split("fit:")[0])
    off = adhesion.load_condition(path)
    assert off.params.v_ref is None and "v_ref" not in off.params.as_dict()
    at_300 = adhesion.peak_adhesion(off, 300 / 3.6).coefficient
    assert at_300 > 2.0 * adhesion.peak_adhesion("hs-wet", 300 / 3.6).coefficient
    assert at_300 / (1 + 300 / 36000) <= adhesion.peak_adhesion(far, 300 / 3.6).coefficient < at_300


def test_a_rolling_speed_factor_out_of_range_is_refused_with_its_line(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(_preset_text("hs-wet").replace("v_ref_kmh: 152.4", "v_ref_kmh: 1"))
    with pytest.raises(InputError, match=r"line 6: params\.v_ref_kmh = 1: .* greater than or equal to 3\.(6|5999)"):
        adhesion.load_condition(path)
