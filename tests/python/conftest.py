"""Paths for the Python tests, from ctest's environment (cmake/ToolincPythonTests.cmake)."""
import os
import pathlib
import subprocess

import pytest

BIN = pathlib.Path(os.environ["TOOLINC_BIN_DIR"])
SOURCE = pathlib.Path(os.environ["TOOLINC_SOURCE_DIR"])
HELD = SOURCE / "data" / "held"


def run_tool(name, *args):
    """Runs an executable, returns its completed process (stdout, stderr as text); never raises."""
    return subprocess.run([str(BIN / name), *map(str, args)], capture_output=True, text=True)


@pytest.fixture
def tool():
    return run_tool
