"""Runs the lecture's tutorial code, solid-sim-tutorial's CHAPTER/simulator.py, unchanged but for
its real-time wait, for STEPS time steps (benchmarks.tutorial runs it as a whole process):

    python benchmarks/tutorial_driver.py CHAPTER STEPS      (from a scratch folder)

The tutorial's loop runs until its window is closed, waiting h between frames. Here its
`pygame.time.wait` returns at once, and after step STEPS - 1 it posts pygame.QUIT, so the loop ends
after step STEPS. Everything else is the tutorial's: each frame drawn before its step (on SDL's
dummy driver when SDL_VIDEODRIVER=dummy), its prints, output/<step>.obj (in the current folder).
On stderr, last, one line of JSON: the steps taken, their CPU time (step_forward's), the Newton
directions beyond each step's first (search_dir's calls - steps: the lines it prints as
"Iteration"), and the scene's numbers as its modules hold them, for the comparison with ours.
"""
import json
import os
import runpy
import sys
import time


def run(chapter, steps):
    sys.path[0] = chapter           # the tutorial's modules (utils, time_integrator...), not ours
    import BarrierEnergy
    import FrictionEnergy
    import GravityEnergy
    import pygame
    import time_integrator
    step_forward, search_dir = time_integrator.step_forward, time_integrator.search_dir
    step_cpu, directions, tol = [], [], []

    def timed_step_forward(*args):     # (x, e, v, m, l2, k, n, o, contact_area, mu, is_DBC, h, tol)
        start = time.process_time()
        result = step_forward(*args)
        step_cpu.append(time.process_time() - start)
        tol[:] = args[-1:]
        return result

    def counted_search_dir(*args):
        directions.append(1)
        return search_dir(*args)

    def no_wait(milliseconds):
        if len(step_cpu) == steps - 1:      # its loop's next pass polls it, then takes a last step
            pygame.event.post(pygame.event.Event(pygame.QUIT))

    time_integrator.step_forward = timed_step_forward
    time_integrator.search_dir = counted_search_dir
    pygame.time.wait = no_wait
    scene = runpy.run_path(os.path.join(chapter, "simulator.py"), run_name="__main__")
    numbers = {name: scene.get(name) for name in ("side_len", "n_seg", "rho", "h", "mu")}
    numbers.update(k=scene["k"][0], slope=list(scene["ground_n"]),
                   slope_point=list(scene["ground_o"]), gravity=list(GravityEnergy.gravity),
                   dhat=BarrierEnergy.dhat, kappa=BarrierEnergy.kappa, epsv=FrictionEnergy.epsv,
                   tol=tol[0])
    return {"steps": len(step_cpu), "step_cpu_s": sum(step_cpu),
            "newton": len(directions) - len(step_cpu), "numbers": numbers}


if __name__ == "__main__":
    done = run(os.path.abspath(sys.argv[1]), int(sys.argv[2]))
    print(json.dumps(done), file=sys.stderr)
