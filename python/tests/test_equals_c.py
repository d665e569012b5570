"""The package's results equal the C program's bitwise: `softbond run` advances the
default scene for 1000 steps and writes a checkpoint; its solver section holds the whole
state in the library's own format, which must equal what the same 1000 steps from Python
save, byte for byte (positions, velocities, clock, statistics), for every integrator."""

import os
import subprocess

import numpy as np
import pytest

import softbond

PROGRAM = os.environ.get("SB_PROGRAM")
SOLVER_MAGIC = b"SBSOLVER"


def start_program(out, scene_path, integrator, duration):
    return subprocess.Popen(
        [PROGRAM, "run", str(scene_path), "--set", f"integrator={integrator}", "--set", f"duration={duration!r}",
         "--set", f"frame_interval={duration!r}", "--checkpoint-every", repr(duration), "--output", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )


def solver_section(out, size):
    data = (out / "checkpoint.sbck").read_bytes()
    start = data.find(SOLVER_MAGIC)
    assert start >= 0, "no solver section in the program's checkpoint"
    return data[start:start + size]


@pytest.mark.skipif(not PROGRAM, reason="SB_PROGRAM (the softbond program) not given")
@pytest.mark.parametrize("integrator", [name for name in softbond.INTEGRATORS if name != "explicit_euler"])
def test_default_scene_equals_the_c_program_bitwise(tmp_path, source_dir, integrator):
    scene_path = source_dir / "scenes" / "default.yaml"
    scene = softbond.Scene.load(scene_path, {"integrator": integrator})
    steps = 1000
    program = start_program(tmp_path, scene_path, integrator, steps * scene.dt)  # runs beside Python's run
    python = softbond.Solver(scene)
    size = len(python.save_state())
    python.advance(scene.dt, steps=steps)
    _, stderr = program.communicate()
    assert program.returncode == 0, stderr
    c_state = solver_section(tmp_path, size)
    from_c = softbond.Solver(scene)
    from_c.load_state(c_state)  # the library checks the format, the model and the set-up
    assert from_c.step_count == steps
    np.testing.assert_array_equal(python.positions, from_c.positions)
    np.testing.assert_array_equal(python.velocities, from_c.velocities)
    assert python.save_state() == c_state


@pytest.mark.skipif(not PROGRAM, reason="SB_PROGRAM (the softbond program) not given")
def test_explicit_euler_fails_as_the_c_program_does(tmp_path, source_dir):
    # The default scene's dt is too large for explicit Euler: both stop at the same step with the same line.
    scene_path = source_dir / "scenes" / "default.yaml"
    scene = softbond.Scene.load(scene_path, {"integrator": "explicit_euler"})
    program = start_program(tmp_path / "out", scene_path, "explicit_euler", 1000 * scene.dt)
    solver = softbond.Solver(scene)
    with pytest.raises(softbond.UnstableError) as error:
        solver.advance(scene.dt, steps=1000)
    _, stderr = program.communicate()
    assert program.returncode != 0
    assert stderr.strip() == f"softbond: {error.value}"
