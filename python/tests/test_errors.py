"""Every error path: the library's line as a softbond.Error subclass, bad arguments as
TypeError/ValueError naming the argument."""

import numpy as np
import pytest

import softbond


def test_error_classes():
    assert issubclass(softbond.InvalidError, softbond.Error)
    assert issubclass(softbond.InvalidError, ValueError)
    assert issubclass(softbond.FileError, OSError)
    for cls in (softbond.ParseError, softbond.DegenerateError, softbond.UnstableError, softbond.BusyError):
        assert issubclass(cls, softbond.Error)


def test_missing_scene_file(tmp_path):
    path = tmp_path / "missing.yaml"
    with pytest.raises(softbond.FileError) as error:
        softbond.Scene.load(path)
    assert str(error.value).startswith(str(path) + ": ")
    assert error.value.status == "io"


def test_unknown_scene_key_names_file_and_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("dt: 0.001\nbond:\n  kk: 3\n")
    with pytest.raises(softbond.ParseError) as error:
        softbond.Scene.load(path)
    assert str(error.value).startswith(f"{path}:3:")
    assert "bond.kk" in str(error.value)


def test_bad_override_is_named(source_dir):
    with pytest.raises(softbond.Error) as error:
        softbond.Scene.load(source_dir / "scenes" / "default.yaml", {"dt": 0})
    assert "dt" in str(error.value)


def test_bad_model_names_the_element():
    with pytest.raises(softbond.InvalidError) as error:
        softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[0, 1], [1, 1]], bond_k=1)
    assert "bond 1" in str(error.value)
    with pytest.raises(softbond.InvalidError) as error:
        softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[0, 2]], bond_k=1)
    assert "bond 0" in str(error.value)


def test_bad_mesh_file(tmp_path):
    path = tmp_path / "broken.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nf 1 2 x\n")
    with pytest.raises(softbond.Error) as error:
        softbond.Model.load(path)
    assert str(path) in str(error.value)


def test_arguments_are_named():
    with pytest.raises(ValueError, match="'vertices' must have shape \\(n, 3\\), got \\(2, 2\\)"):
        softbond.Model.from_arrays([[0, 0], [1, 1]])
    with pytest.raises(TypeError, match="'bonds' must hold integers"):
        softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[0.5, 1]])
    with pytest.raises(ValueError, match="'bonds' holds -1"):
        softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[-1, 1]])
    model = softbond.Model.sheet(nx=3, ny=3)
    with pytest.raises(TypeError, match="unexpected keyword argument 'gravty'"):
        softbond.Solver(model, gravty=(0, 0, 0))
    with pytest.raises(TypeError, match="'drag' must be a number"):
        softbond.Solver(model, drag="a lot")
    with pytest.raises(TypeError, match="'gravity' must be a sequence of 3 numbers"):
        softbond.Solver(model, gravity=(0, 0))
    with pytest.raises(ValueError, match="'integrator'"):
        softbond.Solver(model, integrator="rk4")
    with pytest.raises(TypeError, match="'model' must be a softbond.Model"):
        softbond.Solver("model")
    solver = softbond.Solver(model, threads=1)
    with pytest.raises(ValueError, match="'dt' must be > 0"):
        solver.advance(-1.0)
    with pytest.raises(ValueError, match="'out' must be a writable C-contiguous float64 array of shape \\(9, 3\\)"):
        solver.get_positions(np.empty((9, 3), dtype=np.float32))
    with pytest.raises(TypeError, match="'out' must be a numpy.ndarray"):
        solver.get_positions([0, 0, 0])
    with pytest.raises(ValueError, match="'shape' must be plane"):
        softbond.Collider("cube")


def test_library_refuses_a_bad_collider():
    with pytest.raises(softbond.InvalidError) as error:
        softbond.Collider("sphere", center=(0, 0, 0), radius=-1)
    assert "radius" in str(error.value)


def test_solver_refuses_a_footprint_shorter_than_an_edge():
    model = softbond.Model.sheet(nx=9, ny=9, width=1.0, height=1.0)  # edges up to 0.177 m
    ball = softbond.Collider("sphere", center=(0.5, 0.5, 0.2), radius=0.1, footprint=0.1, name="ball")
    with pytest.raises(softbond.InvalidError) as error:
        softbond.Solver(model, colliders=[ball])
    assert "'ball': footprint 0.1 m is shorter than the longest edge" in str(error.value)


def test_blow_up_raises_unstable():
    model = softbond.Model.from_arrays(
        [[0, 0, 0], [1, 0, 0]], masses=1e-6, bonds=[[0, 1]], bond_k=1e6, rest_lengths=0.5
    )
    solver = softbond.Solver(model, integrator="explicit_euler", gravity=(0, 0, 0), threads=1)
    with pytest.raises((softbond.UnstableError, softbond.DegenerateError)) as error:
        solver.advance(0.01, steps=200)
    assert "step" in str(error.value)


def test_objects_made_without_init_refuse_instead_of_crashing():
    collider = softbond.Collider.__new__(softbond.Collider)
    with pytest.raises(RuntimeError, match="not initialized"):
        collider.set_pose((0, 0, 0))
    with pytest.raises(ValueError, match="colliders\\[0\\] was not initialized"):
        softbond.Solver(softbond.Model.sheet(nx=3, ny=3), colliders=[collider])
    with pytest.raises(RuntimeError, match="not initialized"):
        softbond.Handle.__new__(softbond.Handle).force
    with pytest.raises(RuntimeError, match="not initialized"):
        softbond.StateBuffer.__new__(softbond.StateBuffer).acquire()
    with pytest.raises(RuntimeError, match="not created"):
        softbond.Solver.__new__(softbond.Solver).advance(1.0)


def test_a_state_buffer_of_another_solver_is_refused():
    solver = softbond.Solver(softbond.Model.sheet(nx=3, ny=3), threads=1)
    other = softbond.Solver(softbond.Model.sheet(nx=4, ny=4), threads=1)
    with pytest.raises(softbond.InvalidError, match="'publish' is a StateBuffer of another solver"):
        other.advance(1e-3, publish=softbond.StateBuffer(solver))
    assert other.step_count == 0


def test_numpy_scalars_are_numbers():
    model = softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[0, 1]], bond_k=np.float32(3),
                                       masses=np.int64(2))
    assert list(model.masses) == [2.0, 2.0] and model.terms == ["bond"]
