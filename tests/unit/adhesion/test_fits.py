"""Each adhesion condition's fit: the data sets it was fitted on and checked on (validation cases),
its parameters inside the fit's bounds, or at one with the finding that says which data disagree."""

from importlib import resources

import pytest

from railbrake import adhesion
from railbrake.errors import InputError
from railbrake.validation.adhesion_table import OUTSIDE, data_sets, residual
from railbrake.validation.cases import load_cases
from railbrake.validation.runner import evaluate

SETS = {c.id: c for c in data_sets()}


def _preset_text(name):
    return (resources.files("railbrake") / "data" / "adhesion" / f"{name}.yaml").read_text()


def _values(condition):
    values = dict(vars(condition.params))
    if condition.conditioning is not None:
        values.update(leading_factor=condition.conditioning.leading_factor,
                      recovery_axles=condition.conditioning.recovery_axles)
    return values


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
    values = _values(condition)
    for parameter, (low, high) in condition.fit.bounds.items():
        assert low <= values[parameter] <= high
        if adhesion.at_fit_bound(values[parameter], low, high):
            finding = condition.fit.at_bound.get(parameter, "")
            assert "finding" in finding and "data" in finding, f"{name}.{parameter} at a bound: {finding!r}"


def test_the_parameters_at_a_bound_are_the_two_findings_known():
    at_bound = {(c.name, p) for c in adhesion.conditions() for p in c.fit.at_bound}
    assert at_bound == {("hs-wet", "A"), ("heavy-rain", "leading_factor")}


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
    path.write_text(_preset_text("hs-wet").split("  at_bound:")[0] + "  creep: peaks only\n")
    with pytest.raises(InputError, match=r"fit\.parameters\.A: the value 0\.05 sits at a bound"):
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
