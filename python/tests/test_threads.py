"""The GIL is released while mwst computes: two Python threads triangulate at the same time and
both get the meshes they get alone, and a third Python thread keeps running meanwhile."""

import threading
import time

import numpy as np

import mwst
from conftest import DATA


def test_two_threads_at_once_both_correct():
    points = np.random.default_rng(11).random((40_000, 2))
    plate = mwst.read(str(DATA / "Plate.poly"))
    jobs = {
        "points": lambda: mwst.triangulate(points, method="dr", min_angle=25, threads=1),
        "plate": lambda: mwst.triangulate(plate, method="brh", flip=True, threads=1),
    }
    alone = {name: job() for name, job in jobs.items()}
    together, errors = {}, []
    start = threading.Barrier(len(jobs))

    def run(name):
        try:
            start.wait()
            together[name] = jobs[name]()
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=run, args=(name,)) for name in jobs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for name in jobs:
        np.testing.assert_array_equal(together[name].vertices, alone[name].vertices)
        np.testing.assert_array_equal(together[name].triangles, alone[name].triangles)
        assert together[name].report["weight_total"] == alone[name].report["weight_total"]
        assert mwst.check(together[name], points if name == "points" else plate).ok


def test_another_thread_keeps_running_during_a_long_triangulation():
    """A Python thread counts while the main thread is inside one long mwst.triangulate call. Were
    the GIL held, it could not count at all during the call (at most for one switch interval,
    5 ms, before the call); it must count at a good part of its free-running rate."""
    points = np.random.default_rng(5).random((150_000, 2))
    count = [0]
    running = threading.Event()
    stop = threading.Event()

    def counter():
        running.set()
        while not stop.is_set():
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        running.wait()
        # The counter's rate while the main thread merely sleeps (so holds no GIL).
        c0 = count[0]
        time.sleep(0.2)
        rate = (count[0] - c0) / 0.2
        c1 = count[0]
        t0 = time.perf_counter()
        mesh = mwst.triangulate(points, threads=1)
        seconds = time.perf_counter() - t0
        during = count[0] - c1
    finally:
        stop.set()
        thread.join()
    assert len(mesh.triangles) > 0 and seconds > 0.05
    assert during > 0.2 * rate * seconds, (during, rate, seconds)
