"""Reading paraflex's HDF5 result layout with h5py."""
import h5py
import numpy as np
import pytest

from paraflex_tools import results


@pytest.fixture
def result_file(tmp_path):
    path = tmp_path / "out.h5"
    with h5py.File(path, "w") as f:
        f.attrs["paraflex_version"] = "0.1.0"
        frf = f.create_group("results/1/frf")
        frf["frequency_hz"] = np.array([1.0, 2.0])
        frf["H"] = np.arange(8).reshape(2, 2, 2) * (1 + 1j)
        frf["outputs"] = np.array([b"71:3", b"93:3"])
        frf["inputs"] = np.array(["71:3", "66:3"], dtype=h5py.string_dtype())
        frf.attrs["params"] = [b"E"]
        frf.attrs["values"] = [2.0e11]
        tr = f.create_group("results/2/transient")
        tr["time"] = np.array([0.0, 0.1, 0.2])
        tr["sensors/D71"] = np.array([0.0, 1.0, 2.0])
        tr["outputs"] = np.array([b"71:3", b"93:1"])
        tr["displacement"] = np.arange(6.0).reshape(3, 2)
        f["results/1/modal/frequency_hz"] = np.array([10.0, 20.0])
        f["results/1/modal/shapes"] = np.arange(24.0).reshape(2, 2, 6)
        f["results/1/modal/shapes_grid_ids"] = np.array([7, 9], dtype=np.uint32)
        f["model/grid_ids"] = np.array([1, 7, 9], dtype=np.uint32)
        f["results/3/modal/frequency_hz"] = np.array([5.0])
        f["results/3/modal/shapes"] = np.ones((1, 3, 6))
    return path


def test_texts_decode_bytes_and_keep_str():
    assert results.texts([b"a", "b"]) == ["a", "b"]
    assert results.text(b"x") == "x" and results.text("y") == "y"


def test_frf_names_params_and_pairs(result_file):
    frf = results.read_frf(result_file)
    assert frf.outputs == ["71:3", "93:3"] and frf.inputs == ["71:3", "66:3"]
    assert frf.params == {"E": 2.0e11}
    np.testing.assert_array_equal(frf.pair("93:3", "66:3"), frf.H[:, 1, 1])
    assert frf.H.dtype.kind == "c"


def test_transient_series_by_sensor_or_output(result_file):
    with h5py.File(result_file) as f:
        g = f["results/2/transient"]
        np.testing.assert_array_equal(results.transient_series(g, "sensors", "D71"), [0.0, 1.0, 2.0])
        np.testing.assert_array_equal(results.transient_series(g, "displacement", "93:1"), [1.0, 3.0, 5.0])
        with pytest.raises(KeyError, match="no output 1:1"):
            results.transient_series(g, "displacement", "1:1")


def test_modal_frequencies(result_file):
    np.testing.assert_array_equal(results.modal_frequencies(result_file), [10.0, 20.0])


def test_walk_lists_groups_datasets_and_attributes_sorted(result_file):
    with h5py.File(result_file) as f:
        entries = list(results.walk(f))
    keys = [k for k, _, _ in entries]
    assert keys == sorted(keys)
    kinds = dict((k, kind) for k, kind, _ in entries)
    assert kinds["/"] == "group" and kinds["/@paraflex_version"] == "attribute"
    assert kinds["/results/1/frf/H"] == "dataset" and kinds["/results/1/frf@params"] == "attribute"


def test_modes_carry_the_grid_of_each_row(result_file):
    modes = results.read_modes(result_file)
    np.testing.assert_array_equal(modes.frequency_hz, [10.0, 20.0])
    np.testing.assert_array_equal(modes.grid_ids, [7, 9])
    np.testing.assert_array_equal(modes.of_grid(9), [np.arange(6.0, 12.0), np.arange(18.0, 24.0)])
    with pytest.raises(KeyError, match="grid 1 "):
        modes.of_grid(1)
    every_grid = results.read_modes(result_file, subcase=3)
    np.testing.assert_array_equal(every_grid.grid_ids, [1, 7, 9])


def test_poses_give_axes_and_maps_shaped_like_the_grid(tmp_path):
    path = tmp_path / "poses.h5"
    a, b = np.meshgrid([0.0, 0.5, 1.0], [0.0, 0.2], indexing="ij")
    with h5py.File(path, "w") as f:
        g = f.create_group("results/1/fmb/poses")
        g["values"] = np.stack([a.ravel(), b.ravel()], axis=1)
        g["drives"] = np.array([b"1", b"2"])
        g["shape"] = np.array([3, 2], dtype=np.uint32)
        g["converged"] = np.array([1, 1, 1, 0, 1, 1], dtype=np.uint32)
        g["iterations"] = np.array([5, 3, 3, 0, 3, 3], dtype=np.uint32)
        g["force_residual"] = np.zeros(6)
        g["constraint_residual"] = np.zeros(6)
        g["sensors/T1"] = np.arange(6.0)
        g.attrs["method"] = b"STATICS"
    p = results.read_poses(path)
    assert p.drives == ["1", "2"] and p.shape == (3, 2)
    assert np.array_equal(p.axis(1), [0.0, 0.5, 1.0])
    assert np.array_equal(p.axis("2"), [0.0, 0.2])
    assert p.map("T1")[2, 1] == 5.0
    assert p.converged.tolist() == [True, True, True, False, True, True]
    assert p.attrs["method"] == "STATICS"
