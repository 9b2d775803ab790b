"""The fault kinds the shipped reliability file leaves out, as it says (data/etcs/reliability-hs-emu.yaml):
given in a reliability file they are accepted, run through the plant's components, and none of them
lengthens the emergency stop: a main-reservoir pipe leak (the train has no brake pipe; each car's
check valve keeps its supply reservoir) and a load-weighing valve failed high (its output follows
the BCU's emergency demand) are reported as "no effect on this brake"; a car that does not see the
emergency loop brakes through its EP valve to the same demand (2 cars of the CRH380A from 80 km/h)."""

from railbrake.etcs import model, runs

RELIABILITY = """schema: railbrake.reliability/1
name: t
source: test
failures:
  - {kind: pipe_leak, unit: car, leak_area_mm2: 490.0, per_demand: 1.0e-6, source: "[T] MR hose burst, 25 mm bore"}
  - {kind: pressure_limiter_failed, unit: car, pressure_bar: 8.0, per_demand: 1.0e-6, source: "[T] failed high"}
  - {kind: emergency_loop_lost, unit: car, per_demand: 1.0e-6, source: "[T] loop relay stuck"}
"""


def test_leaks_of_the_line_limiters_failed_high_and_a_lost_loop_do_not_lengthen_the_stop(tmp_path):
    path = tmp_path / "rel.yaml"
    path.write_text(RELIABILITY)
    ctx = runs.context(model.spec("crh380a-8", reliability=path, scatter=None, cars=2, initial_speed_kmh=80,
                                  samples=2, rare_samples=2))
    t_be = model.nominal_build_up(ctx)
    effects, warnings = model.screen(ctx, t_be, model.nominal_decelerations(ctx, t_be, ctx.structs[3].stop_speed))
    by_kind = {}
    for e in effects:
        by_kind.setdefault(e["kind"], []).append(e)
    for kind in ("pipe_leak", "pressure_limiter_failed"):
        assert by_kind[kind] and all(e["no_effect"] for e in by_kind[kind]), by_kind[kind]
        assert any(w.startswith(f"failure {kind}") and "no effect on this brake" in w for w in warnings), warnings
    for e in by_kind["emergency_loop_lost"]:
        assert min(e["ratio"]) >= 1.0 - 1e-3, e
