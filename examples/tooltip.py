#!/usr/bin/env python3
"""tooltip.py CLOUD: the tool frame and tooltip of a cloud in the hand frame, with the toolinc module.

With toolinc installed in PREFIX: PYTHONPATH=PREFIX/lib/python3/dist-packages python3 tooltip.py CLOUD
"""
import sys

import numpy as np
import toolinc

cloud = toolinc.read_cloud(sys.argv[1])  # points (N, 3), colors, normals, frame, viewpoints
frame = toolinc.estimate_tool_frame(cloud)  # a toolinc.ToolFrame; options as estimate-frame's: hand_radius=0.06, ...
tip = toolinc.find_tooltip(cloud, frame=frame)  # a toolinc.Tooltip; tip.to_dict() is find-tooltip's JSON
hand_from_tool = frame.matrix  # a 4x4 numpy array
assert np.isclose(np.linalg.det(hand_from_tool[:3, :3]), 1.0)
print("effector axis", " ".join(f"{v:.3f}" for v in frame.effector_axis))
print("tooltip", " ".join(repr(float(v)) for v in tip.position))
print("confident", "yes" if tip.confidence.confident else "no")
