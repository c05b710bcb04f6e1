"""The planner registry: names, dotted paths, entry points, parameter sets, helpful errors."""

from __future__ import annotations

from importlib.metadata import EntryPoint
from pathlib import Path

import pytest

from nav_bench.errors import InputError, SpecError, UnknownNameError
from nav_bench.planners import registry as reg
from nav_bench.planners.registry import PlannerRegistry, load_planner_set, parse_planner_arg

ROOT = Path(__file__).resolve().parents[2]


def test_unknown_name_suggests_the_closest():
    with pytest.raises(UnknownNameError) as info:
        reg.default_registry().get("dstar_lit")
    assert "Did you mean 'dstar_lite'?" in str(info.value)
    assert info.value.exit_code == 2


def test_registering_a_name_twice_is_an_error():
    r = PlannerRegistry({"eopc": "nav_bench.planners.eopc:EOPC"}, use_entry_points=False)
    with pytest.raises(InputError, match="registered twice"):
        r.register("eopc", "examples.my_planners:Cautious")


def test_entry_point_group_registers_a_planner(monkeypatch):
    ep = EntryPoint(name="cautious", value="examples.my_planners:Cautious", group=reg.ENTRY_POINT_GROUP)
    monkeypatch.setattr(reg, "entry_points", lambda group: [ep] if group == reg.ENTRY_POINT_GROUP else [])
    r = PlannerRegistry(reg.BUILTIN)
    assert "cautious" in r.names() and "eopc" in r.names()
    assert r.get("cautious").__name__ == "Cautious"


def test_entry_point_clashing_with_a_builtin_is_refused(monkeypatch):
    ep = EntryPoint(name="eopc", value="examples.my_planners:Cautious", group=reg.ENTRY_POINT_GROUP)
    monkeypatch.setattr(reg, "entry_points", lambda group: [ep])
    with pytest.raises(InputError, match="'eopc' is registered twice"):
        PlannerRegistry(reg.BUILTIN)


def test_dotted_path_loads_a_user_planner_with_overrides():
    spec = parse_planner_arg("examples.my_planners:Cautious:v_max=0.3,stop_m=0.5")
    assert spec.planner == "examples.my_planners:Cautious"
    assert spec.params == {"v_max": 0.3, "stop_m": 0.5}
    planner = reg.make_planner(spec)
    assert planner.p == {"v_max": 0.3, "stop_m": 0.5, "k_turn": 1.5}


def test_dotted_path_to_something_that_is_not_a_planner():
    with pytest.raises(InputError, match="not a nav_bench Planner"):
        reg.default_registry().get("nav_bench.errors:InputError")
    with pytest.raises(InputError, match="cannot import planner module"):
        reg.default_registry().get("no_such_module_xyz:Planner")


def test_parameter_set_file_and_name_with_overrides():
    paper = parse_planner_arg(str(ROOT / "configs/planners/eopc_paper.yaml"))
    assert paper.planner == "eopc"
    over = parse_planner_arg("eopc:RR=0.4,ipo_mode=raw")
    full = reg.full_params(over)
    assert full["RR"] == 0.4 and full["ipo_mode"] == "raw"
    assert full["lambda1"] == 0.8  # untouched defaults filled in


@pytest.mark.parametrize("text, words", [
    ("eopc:RR=abc", "expects a number"),
    ("eopc:ipo_mode=sum", "must be one of"),
    ("eopc:replan_on=never", r"replan_on' must be one of \['blocked_path', 'stop'\]"),
    ("eopc:blocked_by=wall", r"blocked_by' must be one of \['segment', 'corridor'\]"),
    ("eopc:RR", "not key=value"),
    ("eopc:lambda=0.5", "has no parameter 'lambda'"),
])
def test_bad_overrides_say_what_is_expected(text, words):
    with pytest.raises(InputError, match=words):
        parse_planner_arg(text)


def test_unknown_parameter_in_a_file_names_file_key_and_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("planner: eopc\nparams:\n  RR: 0.5\n  lamda1: 0.9\n")
    with pytest.raises(SpecError) as info:
        parse_planner_arg(str(path))
    err = info.value
    assert (err.file, err.key_path, err.line) == (str(path), "params.lamda1", 4)
    assert "Did you mean 'lambda1'?" in err.problem



def _files_of_defaults() -> dict[str, bool]:
    """The planner files whose header says they hold their planner's defaults: file stem ->
    whether they list every parameter ("spelled out") or a part (eopc_paper: the paper's)."""
    files = {}
    for path in sorted((ROOT / "configs/planners").glob("*.yaml")):
        text = path.read_text()
        if "spelled out" in text or "every value here is the planner's default" in text:
            files[path.stem] = "spelled out" in text
    return files


def test_the_baselines_and_eopc_paper_are_files_of_defaults() -> None:
    assert {"apf", "bug2", "dstar_lite", "dwa", "dwa_global", "eopc_paper", "tangent_bug",
            "vfh_plus"} <= set(_files_of_defaults())


@pytest.mark.parametrize("stem, complete", sorted(_files_of_defaults().items()))
def test_a_file_of_defaults_equals_the_planners_params(stem: str, complete: bool) -> None:
    # the defaults have two homes, the planner's Param list and this file: they must not drift
    spec = load_planner_set(ROOT / "configs/planners" / f"{stem}.yaml")
    defaults = {p.name: p.default for p in reg.default_registry().get(spec.planner).params}
    assert spec.params == {name: defaults[name] for name in spec.params}
    if complete:
        assert set(spec.params) == set(defaults)


def test_a_neutral_parameter_is_left_out_of_the_ids() -> None:
    """D* Lite's search_kernel changes how it computes, not what: the parameter set's id (and
    so the episodes' random streams and job ids) is that of the set without it, and it is the
    same whichever kernel is asked for; any other parameter changes the id."""
    from nav_bench.ids import params_id
    from nav_bench.specs import PlannerSetSpec

    def full(**params: object) -> dict:
        return reg.full_params(PlannerSetSpec(planner="dstar_lite", params=params))

    auto, python = full(), full(search_kernel="python")
    assert auto["search_kernel"] == "auto" and python["search_kernel"] == "python"  # rows record it
    without = {k: v for k, v in auto.items() if k != "search_kernel"}
    assert reg.identity_params("dstar_lite", python) == without
    assert reg.set_id("dstar_lite", auto) == reg.set_id("dstar_lite", python) == params_id("dstar_lite", without)
    assert reg.set_id("dstar_lite", full(lookahead=0.6)) != reg.set_id("dstar_lite", auto)
