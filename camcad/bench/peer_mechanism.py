"""Run the PyPI package ``mechanism`` (a peer of camcad) on one cam and print one JSON object.

Runs with the python of the peer's own virtual environment (``camcad.bench.peers.peer_python``), never in
camcad's, and imports nothing from camcad. Settings on stdin as JSON: ``lift_mm``, ``base_radius_mm``,
``roller_radius_mm``, ``steps_rad`` (the package's θ step h), ``repeats``. For each h it prints the θ grid,
the pitch curve ``Motion.get_profile(Rb + Rr, thetas_r)`` and the roller profile made from it by the
normal-offset fix (the package offsets its pitch curve radially by Rr, which is exact only for a knife edge;
the fix moves each pitch point by Rr along the normal of the pitch polyline, from central differences), in
the package's frame (follower on +x, the point of cam angle θ at polar angle −θ), and the median CPU time of
``Cam(...)`` + ``get_profile`` + the fix.

The cam: dwell 90°, cycloidal rise, dwell 90°, cycloidal return (90° each), counter-clockwise.
"""

from __future__ import annotations

import json
import statistics
import sys
import time


def main() -> None:
    import importlib.metadata

    import numpy as np
    from mechanism import Cam

    settings = json.load(sys.stdin)
    lift, rb, rr = (float(settings[k]) for k in ("lift_mm", "base_radius_mm", "roller_radius_mm"))
    motion = [("Dwell", 90), ("Rise", lift, 90), ("Dwell", 90), ("Fall", lift, 90)]
    runs = []
    for step in settings["steps_rad"]:
        def build(step=step):
            cam = Cam(motion=motion, degrees=True, omega=1.0, rotation="ccw", h=step)
            x, y = cam.cycloidal.get_profile(rb + rr, cam.thetas_r)
            pitch = np.stack((x, y), axis=1)
            tangent = np.roll(pitch, -1, axis=0) - np.roll(pitch, 1, axis=0)      # the normal-offset fix
            normal = np.stack((tangent[:, 1], -tangent[:, 0]), axis=1)
            normal /= np.hypot(normal[:, 0], normal[:, 1])[:, None]
            normal *= np.sign(np.einsum("ij,ij->i", normal, pitch))[:, None]     # outward
            return cam, pitch, pitch - rr * normal

        times = []
        for _ in range(int(settings["repeats"])):
            start = time.process_time()
            cam, pitch, profile = build()
            times.append(time.process_time() - start)
        runs.append({"step_rad": step, "theta": cam.thetas.tolist(), "pitch": pitch.tolist(),
                     "profile": profile.tolist(), "cpu_s": statistics.median(times)})
    json.dump({"version": importlib.metadata.version("mechanism"), "runs": runs}, sys.stdout)


if __name__ == "__main__":
    main()
