"""Shared fixtures of the Python package's tests.

Run from the project root with the built package on the path:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest python/tests
The command line they compare against is $MWST_CLI, or the `mwst` next to the package's build tree
(<build>/mwst). MWST_SLOW_TESTS=1 also runs opt on every data set (minutes).
"""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import mwst

PROJECT = pathlib.Path(__file__).resolve().parents[2]
DATA = PROJECT / "data"
SLOW = os.environ.get("MWST_SLOW_TESTS") == "1"


def _cli_path():
    given = os.environ.get("MWST_CLI")
    if given:
        return pathlib.Path(given)
    # <build>/python/mwst/__init__.py -> <build>/mwst
    return pathlib.Path(mwst.__file__).resolve().parents[2] / "mwst"


CLI = _cli_path()


@pytest.fixture(scope="session")
def cli():
    """Runs the command line; returns its completed process (check=True)."""
    if not CLI.is_file():
        pytest.fail(f"the command line {CLI} is missing: build the target mwst_cli, or set MWST_CLI")

    def run(*args, check=True):
        return subprocess.run([str(CLI), *map(str, args)], check=check, capture_output=True, text=True)

    return run


def cli_triangulate(cli, tmp_path, input_path, *options):
    """`mwst triangulate INPUT OPTIONS` into tmp_path: (report dict, mesh prefix)."""
    prefix = tmp_path / (pathlib.Path(input_path).stem + "-cli")
    report = tmp_path / (prefix.name + ".json")
    cli("triangulate", input_path, "-o", prefix, "--json", report, "-q", *options)
    return json.loads(report.read_text()), str(prefix)


def canonical_triangles(vertices, triangles):
    """The triangles as sorted rows of sorted corner coordinates: equal for two meshes made of the
    same triangles, however their vertices and triangles are numbered."""
    corners = np.asarray(vertices)[np.asarray(triangles, dtype=np.int64)]  # (m, 3, 2)
    order = np.lexsort((corners[:, :, 1], corners[:, :, 0]), axis=1)
    corners = np.take_along_axis(corners, order[:, :, None], axis=1).reshape(len(corners), 6)
    return corners[np.lexsort(corners.T[::-1])]


def square_with_hole():
    """A 4 x 4 square with a 2 x 2 square hole in the middle: (vertices, segments, holes)."""
    vertices = np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]], dtype=float)
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    holes = np.array([[2.0, 2.0]])
    return vertices, segments, holes
