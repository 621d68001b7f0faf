"""Long calls release the GIL: a pure-Python counter thread keeps counting
while the Rust call runs. What is measured is work, not time: the number of
increments the counter made while the main thread was inside the call. With
the GIL held it could count only in the switches at the call's two ends;
released, it counts through the whole call. A C loop that holds the GIL as
long is the control (about 1 % of the released count seen here)."""

import sys
import threading

import numpy as np

import extrinsic_audit as ea


class Counter(threading.Thread):
    def __init__(self):
        super().__init__(daemon=True)
        self.inside = 0  # increments made while `busy` was set
        self.busy = False
        self.stop = False
        self.running = threading.Event()

    def run(self):
        self.running.set()
        while not self.stop:
            if self.busy:
                self.inside += 1


def counted(call):
    old = sys.getswitchinterval()
    sys.setswitchinterval(1e-5)
    c = Counter()
    c.start()
    c.running.wait()
    try:
        c.busy = True
        result = call()
        c.busy = False
    finally:
        c.stop = True
        c.join()
        sys.setswitchinterval(old)
    return c.inside, result


def raw_cloud(n=150_000, seed=1):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-20, 20, (n, 2))
    return np.column_stack([xy, 0.01 * rng.standard_normal(n)])


def test_degeneracy_releases_the_gil():
    pts = raw_cloud()
    inside, rep = counted(lambda: ea.degeneracy(pts, radius=0.6))
    assert rep.points > 0
    assert inside > 10_000, inside
    # The control, a C loop that keeps the GIL for as long (builtin sum over
    # a range: no bytecode, no switch): the counter is starved there, so the
    # count above is the release, not the counter's own pace.
    held, _ = counted(lambda: sum(range(40_000_000)))
    assert held < inside / 10, (held, inside)
