"""`python -m benchmarks.speed --window` (benchmarks/waits.py): the window's pacing at n_seg 4, 8
and 16, on the dummy driver and, where there is a display, on it too (the measurements are
stubbed, but for one run of 5 steps: test_the_window_benchmark_runs)."""
from benchmarks import waits


def fake_measure(calls):
    def window_real_time(n_seg, speed_=1.0, duration=3.0, driver=waits.MEMORY_DRIVER):
        calls.append((n_seg, speed_, driver))
        return {"n_seg": n_seg, "speed": speed_, "driver": driver, "wall_per_simulated": 1.0,
                "cpu_per_simulated": 0.5, "busy": 0.5, "frames": 60, "slow_frames": 0,
                "lowest_rate": 1.0}
    return window_real_time


def test_the_table_covers_n_seg_4_8_16_on_every_driver_found(monkeypatch):
    for display, drivers in ((None, ["dummy"]), ("x11", ["dummy", "x11"])):
        calls = []
        monkeypatch.setattr(waits, "window_real_time", fake_measure(calls))
        monkeypatch.setattr(waits, "display_driver", lambda: display)
        table = waits.window_table()
        assert {n for n, _, _ in calls} == {4, 8, 16} and {d for _, _, d in calls} == set(drivers)
        assert len(calls) == 3 * len(drivers) * 2                          # speed 1 and flat out
        assert all(f"  {n:>5}  {d:>6}" in table for n, _, d in calls)


def test_no_display_means_the_dummy_driver_only(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    assert waits.display_driver() is None


def test_the_window_benchmark_runs():
    """benchmarks.speed --window's measurement, on a run of 5 steps played flat out."""
    r = waits.window_real_time(4, speed=100.0, duration=0.05)
    assert r["frames"] >= 1 and 0.0 < r["busy"] <= 1.0 and r["cpu_per_simulated"] > 0.0
    assert r["wall_per_simulated"] > 0.0
