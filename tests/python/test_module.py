"""The toolinc Python module: the executables' results on numpy arrays, their options and their errors."""
import json

import numpy as np
import pytest
from conftest import HELD

import toolinc  # noqa: E402  (built by CMake, on PYTHONPATH from ctest)


def cli_json(tool, *args):
    run = tool(*args, "-o", "-", "-q")
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


@pytest.mark.parametrize("family", ["hoe", "hook", "stick", "t-bar", "flat-top"])
def test_tooltip_equals_find_tooltip(tool, family):
    cloud = HELD / f"{family}.ply"
    expected = cli_json(tool, "find-tooltip", cloud)
    tip = toolinc.find_tooltip(toolinc.read_cloud(str(cloud)))
    assert isinstance(tip, toolinc.Tooltip) and isinstance(tip, toolinc.Result)
    assert isinstance(tip.position, np.ndarray) and tip.position.shape == (3,)
    assert tip.confidence.confident == expected["confidence"]["confident"]
    # Attributes and items are the same fields; to_dict() is the executable's JSON.
    assert tip.position is tip["position"] and "position" in tip and "no_such_field" not in tip
    assert set(tip.to_dict()) == set(expected) and json.dumps(tip.to_dict()["confidence"])
    with pytest.raises(AttributeError):
        tip.no_such_field  # noqa: B018
    assert np.max(np.abs(tip["position"] - np.array(expected["position"]))) <= 1e-9
    assert np.max(np.abs(tip["tool_frame"] - np.array(expected["tool_frame"]))) <= 1e-9


def test_frame_equals_estimate_frame_with_options(tool):
    cloud = HELD / "hook.ply"
    expected = cli_json(tool, "estimate-frame", cloud, "--hand-radius", "0.07", "--voxel-size", "0.004")
    frame = toolinc.estimate_tool_frame(toolinc.read_cloud(str(cloud)), hand_radius=0.07,
                                        config={"voxel-size": 0.004, "hand-radius": 0.05})  # the keyword wins
    assert isinstance(frame, toolinc.ToolFrame) and frame.matrix.shape == (4, 4)
    assert np.max(np.abs(frame["matrix"] - np.array(expected["matrix"]))) <= 1e-9
    assert frame["settings"]["hand-radius"] == 0.07


def test_config_file_as_with_c(tool, tmp_path):
    cloud = HELD / "l-stick.ply"
    config = tmp_path / "config.json"
    config.write_text(json.dumps({"hand-radius": 0.07, "find-tooltip": {"rule": "weighted", "effector-weight": 0.6},
                                  "align-pose": {"roll-step-deg": 10}}))
    expected = cli_json(tool, "find-tooltip", cloud, "-c", config)
    tip = toolinc.find_tooltip(toolinc.read_cloud(str(cloud)), config=str(config))
    assert tip["settings"]["rule"] == "weighted" and tip["settings"]["effector-weight"] == 0.6
    assert np.max(np.abs(tip["position"] - np.array(expected["position"]))) <= 1e-9
    # The keywords win over the file, as the command line does.
    expected = cli_json(tool, "find-tooltip", cloud, "-c", config, "--effector-weight", "0.9")
    tip = toolinc.find_tooltip(toolinc.read_cloud(str(cloud)), config=str(config), effector_weight=0.9)
    assert np.max(np.abs(tip["position"] - np.array(expected["position"]))) <= 1e-9
    assert tip["settings"]["effector-weight"] == 0.9


def test_given_frame_and_plain_arrays(tool):
    cloud = toolinc.read_cloud(str(HELD / "rake.ply"))
    frame = toolinc.estimate_tool_frame(cloud)
    expected = toolinc.find_tooltip(cloud)
    # A frame dict as estimate_tool_frame returns it; viewpoints travel with the cloud dict, so the plain
    # (N, 3) array (no viewpoints) is given the frame computed with them.
    tip = toolinc.find_tooltip(cloud["points"], frame=frame)
    assert np.allclose(tip.position, expected.position, atol=1e-12)
    # The frame as a plain dict, as json.load gives it, works too.
    tip = toolinc.find_tooltip(cloud["points"], frame=frame.to_dict())
    assert np.allclose(tip.position, expected.position, atol=1e-12)


def test_errors_carry_the_cli_messages(tool, tmp_path):
    missing = tmp_path / "missing.ply"
    run = tool("find-tooltip", missing, "-o", "-")
    assert run.returncode == 2
    with pytest.raises(toolinc.InputError) as error:
        toolinc.read_cloud(str(missing))
    assert str(error.value) in run.stderr
    assert isinstance(error.value, ValueError)

    cloud = HELD / "hoe.ply"
    run = tool("find-tooltip", cloud, "--hand-radius", "-1", "-o", "-")
    assert run.returncode == 2
    with pytest.raises(toolinc.InputError) as error:
        toolinc.find_tooltip(toolinc.read_cloud(str(cloud)), hand_radius=-1)
    assert str(error.value) in run.stderr
    with pytest.raises(toolinc.InputError, match="no-such-option"):
        toolinc.estimate_tool_frame(toolinc.read_cloud(str(cloud)), no_such_option=1)

    # Every point inside the hand: the method cannot work (exit 3).
    inside = np.random.default_rng(0).uniform(-0.02, 0.02, size=(500, 3))
    toolinc.write_ply(str(tmp_path / "inside.ply"), inside)
    run = tool("estimate-frame", tmp_path / "inside.ply", "-o", "-")
    assert run.returncode == 3
    with pytest.raises(toolinc.MethodError) as error:
        toolinc.estimate_tool_frame(inside)
    assert str(error.value) in run.stderr


def test_merge_views_equals_merge_views(tool, tmp_path):
    session, views = tmp_path / "session", tmp_path / "views"
    assert tool("simulate-session", "--family", "hoe", "--seed", 4, "-o", session, "-q").returncode == 0
    tool("crop-cloud", session, "--all", "-o", views, "-q")
    clouds = sorted(views.glob("*.ply"))
    assert tool("merge-views", *clouds, "-o", tmp_path / "model.ply", "--voxel-size", "0.003", "-q").returncode == 0
    model, report = toolinc.merge_views([toolinc.read_cloud(str(c)) for c in clouds], voxel_size=0.003)
    expected = toolinc.read_cloud(str(tmp_path / "model.ply"))
    assert isinstance(report, toolinc.MergeReport) and report.type == "merge_report" and report.ok
    assert model["points"].shape == expected["points"].shape
    # The PLY stores float32 coordinates.
    assert np.max(np.abs(model["points"] - expected["points"])) <= 1e-6
    assert len(model["viewpoints"]) == len(expected["viewpoints"]) > 0
    # Which views saw each point, as the PLY's views property carries it.
    assert np.array_equal(model["views"], expected["views"]) and model["views"].min() > 0


def test_align_pose_finds_the_grasp(tool, tmp_path):
    model, held, truth = tmp_path / "model.ply", tmp_path / "held.ply", tmp_path / "truth.json"
    assert tool("generate-tool", "--family", "hoe", "-o", model, "-q").returncode == 0
    assert tool("generate-tool", "--family", "hoe", "--grasp-seed", 5, "--truth", truth, "-o", held, "-q").returncode == 0
    expected = cli_json(tool, "align-pose", "--model", model, "--view", held)
    pose = toolinc.align_pose(toolinc.read_cloud(str(model)), toolinc.read_cloud(str(held)))
    assert isinstance(pose, toolinc.ToolPose) and pose.type == "tool_pose"
    assert np.max(np.abs(pose["matrix"] - np.array(expected["matrix"]))) <= 1e-9
    grasp = np.array(json.loads(truth.read_text())["hand_from_canonical"])
    assert np.max(np.abs(pose["matrix"][:3, 3] - grasp[:3, 3])) < 0.01  # the grasp, to the noise of one view
