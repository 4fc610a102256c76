"""`neurotree mcp` driven by the Model Context Protocol's Python SDK (`mcp` on PyPI) as an
assistant's client would drive it: over stdin/stdout, with the initialize handshake
(mode="legacy") and with the current revision's discovery (mode="auto").

The binary is $NEUROTREE (default: target/debug/neurotree); `.ci/run` builds it first.
"""

import json
import os
import pathlib
import subprocess

import anyio
import pytest
from mcp import Client, StdioServerParameters

ROOT = pathlib.Path(__file__).resolve().parents[4]
BINARY = os.environ.get("NEUROTREE", str(ROOT / "target" / "debug" / "neurotree"))

UNREACHABLE = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Fallback>
      <AlwaysSuccess/>
      <AlwaysFailure/>
    </Fallback>
  </BehaviorTree>
</root>"""

PICK = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Detect object="{target}"/>
      <Grasp object="{target}"/>
    </Sequence>
  </BehaviorTree>
</root>"""


def server(folder):
    return StdioServerParameters(command=BINARY, args=["mcp"], cwd=str(folder))


def call(folder, mode, tool, arguments):
    """The result of one call of `tool`, on a fresh server started in `folder`."""

    async def go():
        async with Client(server(folder), mode=mode) as client:
            return await client.call_tool(tool, arguments)

    return anyio.run(go)


MODES = ["legacy", "auto"]


@pytest.mark.parametrize("mode", MODES)
def test_the_tools_are_listed_with_their_schemas(tmp_path, mode):
    async def go():
        async with Client(server(tmp_path), mode=mode) as client:
            return client.protocol_version, await client.list_tools()

    version, listed = anyio.run(go)
    assert version == ("2025-11-25" if mode == "legacy" else "2026-07-28")
    names = sorted(t.name for t in listed.tools)
    assert names == sorted([
        "check_tree", "lint_tree", "list_node_types", "run_scenario", "run_tree",
        "show_tree", "simulate_nav2",
    ])
    for tool in listed.tools:
        if tool.name not in ("list_node_types", "simulate_nav2"):
            assert "xml" in tool.input_schema["properties"], tool.name
            assert "xml" in tool.input_schema["required"], tool.name


@pytest.mark.parametrize("mode", MODES)
def test_lint_tree_reports_the_unreachable_child(tmp_path, mode):
    result = call(tmp_path, mode, "lint_tree", {"xml": UNREACHABLE})
    assert not result.is_error
    found = result.structured_content["diagnostics"]
    assert [(d["code"], d["line"], d["rule"]) for d in found] == [("NT0201", 5, "unreachable-child")]
    assert "tree.xml:5:7: warning[NT0201]" in result.content[0].text


def test_check_tree_gives_each_error_its_place(tmp_path):
    result = call(tmp_path, "legacy", "check_tree", {"xml": PICK})
    assert not result.is_error
    errors = result.structured_content["errors"]
    assert result.structured_content["ok"] is False
    assert errors[0]["line"] == 4 and errors[0]["kind"] == "UnknownNode"
    ok = call(tmp_path, "legacy", "check_tree", {"xml": UNREACHABLE})
    assert ok.structured_content == {"ok": True, "trees": 1, "errors": [], "warnings": []}


def test_show_tree_draws_mermaid(tmp_path):
    result = call(tmp_path, "auto", "show_tree", {"xml": UNREACHABLE, "format": "mermaid"})
    assert not result.is_error
    text = result.structured_content["text"]
    assert "Fallback" in text and "AlwaysSuccess" in text
    assert text.lstrip().startswith(("graph", "flowchart")), text


def test_run_tree_mocks_leaves_and_tells_why_it_failed(tmp_path):
    result = call(tmp_path, "legacy", "run_tree", {
        "xml": PICK,
        "mocks": {"Detect": "RUNNING,SUCCESS", "Grasp": "FAILURE"},
        "max_ticks": 10,
    })
    assert not result.is_error, result.content[0].text
    out = result.structured_content
    assert out["status"] == "FAILURE"
    assert [t["status"] for t in out["ticks"]] == ["RUNNING", "FAILURE"]
    assert out["summary"]["nodes"]["Detect"]["ticks"] == 2
    assert out["summary"]["nodes"]["Grasp"]["ticks"] == 1
    assert "failure" in out["summary"]
    assert out["coverage"] is not None


def test_run_tree_stops_at_its_tick_limit(tmp_path):
    result = call(tmp_path, "legacy", "run_tree", {
        "xml": PICK, "mocks": {"Detect": "RUNNING"}, "max_ticks": 5,
    })
    out = result.structured_content
    assert out["stopped_at_max_ticks"] is True
    assert len(out["ticks"]) == 5
    too_many = call(tmp_path, "legacy", "run_tree", {"xml": PICK, "max_ticks": 10**9})
    assert too_many.is_error


def test_run_scenario_passes_and_fails_with_the_reason(tmp_path):
    scenario = """
name = "grasp fails"
tree = "ignored.xml"
mock_unknown = true
[mocks]
Grasp = "FAILURE"
[[expect]]
root = "%s"
"""
    passed = call(tmp_path, "legacy", "run_scenario", {"xml": PICK, "scenario": scenario % "FAILURE"})
    assert passed.structured_content["passed"] is True, passed.structured_content["text"]
    failed = call(tmp_path, "legacy", "run_scenario", {"xml": PICK, "scenario": scenario % "SUCCESS"})
    assert failed.structured_content["passed"] is False
    assert "SUCCESS" in failed.structured_content["text"], failed.structured_content["text"]


def test_list_node_types_knows_nav2(tmp_path):
    result = call(tmp_path, "legacy", "list_node_types", {"nav2": True})
    types = {t["name"]: t for t in result.structured_content["types"]}
    assert "ComputePathToPose" in types and "Sequence" in types
    ports = {p["name"]: p for p in types["ComputePathToPose"]["ports"]}
    assert ports["path"]["direction"] == "output"


def test_a_model_declares_node_types_for_every_tool(tmp_path):
    model = """<root BTCPP_format="4"><TreeNodesModel>
      <Action ID="Detect"><output_port name="object" type="std::string">What it saw</output_port></Action>
      <Action ID="Grasp"><input_port name="object" type="std::string"/></Action>
    </TreeNodesModel></root>"""
    listed = call(tmp_path, "legacy", "list_node_types", {"model_xml": model})
    types = {t["name"]: t for t in listed.structured_content["types"]}
    assert types["Detect"]["ports"][0]["direction"] == "output"
    assert types["Detect"]["ports"][0]["description"] == "What it saw"
    checked = call(tmp_path, "legacy", "check_tree", {"xml": PICK, "model_xml": model})
    assert checked.structured_content["ok"] is True, checked.structured_content
    linted = call(tmp_path, "legacy", "lint_tree", {"xml": PICK, "model_xml": model})
    assert linted.structured_content["diagnostics"] == []


def test_simulate_nav2_arrives(tmp_path):
    result = call(tmp_path, "legacy", "simulate_nav2", {"goal": [6.5, 1.5]})
    assert not result.is_error, result.content[0].text
    out = result.structured_content
    assert out["arrived"] is True, out["text"]
    assert out["status"] == "SUCCESS"
    assert out["ticks"] > 0


def test_bad_input_is_an_error_and_the_server_goes_on(tmp_path):
    async def go():
        async with Client(server(tmp_path), mode="legacy") as client:
            bad = await client.call_tool("lint_tree", {"xml": "<root"})
            huge = await client.call_tool("lint_tree", {"xml": "x" * (2 << 20)})
            good = await client.call_tool("lint_tree", {"xml": UNREACHABLE})
            return bad, huge, good

    bad, huge, good = anyio.run(go)
    assert not bad.is_error
    assert bad.structured_content["diagnostics"][0]["code"] == "NT0001"
    assert huge.is_error and "bytes" in huge.content[0].text
    assert good.structured_content["warnings"] == 1


def test_malformed_json_rpc_is_answered_and_serving_goes_on(tmp_path):
    lines = [
        "{oops",
        json.dumps({"jsonrpc": "2.0", "id": 1, "method": "tools/call", "params": {"name": "nope"}}),
        json.dumps({"jsonrpc": "2.0", "id": 2, "method": "ping"}),
    ]
    done = subprocess.run([BINARY, "mcp"], input="\n".join(lines) + "\n", capture_output=True,
                          text=True, cwd=tmp_path, timeout=60)
    answers = [json.loads(line) for line in done.stdout.splitlines()]
    assert [a.get("error", {}).get("code") for a in answers] == [-32700, -32602, None]
    assert answers[2] == {"jsonrpc": "2.0", "id": 2, "result": {}}
    assert done.returncode == 0


def test_the_server_leaves_nothing_behind(tmp_path):
    call(tmp_path, "legacy", "run_tree", {"xml": UNREACHABLE})
    assert list(tmp_path.iterdir()) == []
