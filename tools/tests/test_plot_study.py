"""tools/optimize/plot_study.py on a study group of the layout SOL OPTIMIZE writes."""
import importlib.util

import h5py
import numpy as np

from paraflex_tools import REPO


def load_plot_study():
    spec = importlib.util.spec_from_file_location("plot_study", REPO / "tools" / "optimize" / "plot_study.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_reads_a_study_and_draws_its_front(tmp_path):
    path = tmp_path / "study.h5"
    strings = h5py.string_dtype()
    with h5py.File(path, "w") as f:
        g = f.create_group("results/1/optimize")
        g["designs"] = np.array([[0.0, 1.0], [1.0, 2.0], [2.0, 3.0], [3.0, 4.0]])
        g["responses"] = np.array([[1.0, 4.0, 0.0], [4.0, 1.0, 0.0], [3.0, 3.0, 9.0], [np.nan, np.nan, np.nan]])
        g["feasible"] = np.array([1, 1, 0, 0], dtype=np.uint32)
        g["pareto"] = np.array([0, 1], dtype=np.uint32)
        g["hypervolume"] = np.array([1.0, 2.0, 2.0, 2.0])
        g.attrs.create("objectives", ["F1", "F2"], dtype=strings)
        g.attrs.create("responses", ["F1", "F2", "C"], dtype=strings)
        for label, design in [("best_F1", 0), ("best_F2", 1), ("knee", 0)]:
            g.create_group(f"representative/{label}").attrs["design"] = design
    plot_study = load_plot_study()
    study = plot_study.read_study(path, "1")
    assert study["objectives"] == ["F1", "F2"]
    assert study["representatives"] == {"best_F1": 0, "best_F2": 1, "knee": 0}
    out = tmp_path / "study.png"
    plot_study.draw(study, "study").savefig(out)
    assert out.stat().st_size > 0
