"""The solve releases the GIL, and Ctrl-C interrupts a solve or a sweep."""

import subprocess
import sys
import textwrap
import threading
import time

import pytest

import contactdd


def test_gil_released():
    problem = contactdd.notch_benchmark(nx=256, ny=128)
    window = {}

    def run():
        window["start"] = time.perf_counter()
        window["result"] = contactdd.solve(problem, gamma=0.05, tol=1e-8, max_iter=5000)
        window["end"] = time.perf_counter()

    worker = threading.Thread(target=run)
    stamps = []
    count = 0
    worker.start()
    while worker.is_alive():
        count += 1
        if count % 1000 == 0:
            stamps.append(time.perf_counter())
    worker.join()
    assert window["result"].converged
    start, end = window["start"], window["end"]
    assert end - start > 0.05, "the solve was too quick to tell"
    # The main thread kept counting while the solve ran in the other thread.
    middle = [t for t in stamps if start + 0.1 * (end - start) < t < end - 0.1 * (end - start)]
    assert len(middle) >= 5, (len(middle), end - start, count)


@pytest.mark.parametrize(
    "call",
    [
        "contactdd.solve(problem, gamma=1e-4, tol=1e-14, max_iter=10**9)",
        # Every run of the sweep is endless, so only a cancel inside the runs stops it.
        "contactdd.sweep(problem, methods=['active-set', 'robin'], gammas=[1e-4, 2e-4],"
        " tol=1e-14, max_iter=10**9)",
    ],
    ids=["solve", "sweep"],
)
def test_ctrl_c_interrupts(call):
    script = textwrap.dedent(
        f"""
        import os, signal, threading, time
        import contactdd
        # A process started in the background inherits SIGINT ignored; the test is about
        # contactdd's handling, so install Python's own handler whatever the parent did.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        problem = contactdd.notch_benchmark()
        threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        t = time.perf_counter()
        try:
            {call}
            print("finished")
        except KeyboardInterrupt:
            print("interrupted", time.perf_counter() - t)
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    word, seconds = out.stdout.split()
    assert word == "interrupted"
    assert float(seconds) < 5.0


def test_threads_argument(notch):
    one = contactdd.solve(notch, threads=1)
    two = contactdd.solve(notch, threads=2)
    assert one.iterations == two.iterations
    assert (one.contact[0].pressure == two.contact[0].pressure).all()


def test_ctrl_c_during_setup_is_prompt():
    """Ctrl-C during the assembly and factorisation (several seconds on this P2 mesh) raises
    KeyboardInterrupt at once, not when the setup ends."""
    script = textwrap.dedent(
        """
        import os, signal, threading, time
        import contactdd
        signal.signal(signal.SIGINT, signal.default_int_handler)
        problem = contactdd.notch_benchmark(nx=384, ny=192, order="p2")
        sent = {}
        def interrupt():
            sent["t"] = time.perf_counter()
            os.kill(os.getpid(), signal.SIGINT)
        threading.Timer(1.0, interrupt).start()
        t = time.perf_counter()
        try:
            contactdd.solve(problem, max_iter=1, check=False)
            print("finished", time.perf_counter() - t)
        except KeyboardInterrupt:
            print("interrupted", time.perf_counter() - sent["t"])
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    word, seconds = out.stdout.split()
    assert word == "interrupted", out.stdout
    assert float(seconds) < 1.0, "KeyboardInterrupt came late"
