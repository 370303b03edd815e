"""examples/tuning.ipynb runs, every cell, in an ipykernel of this venv (nbclient, pinned
in python/requirements-dev.txt): its sweep, optimizer and ranges cells assert their own
results, so a change that breaks the tuning loop from Python fails here."""

import pathlib
import time

import nbclient
import nbformat

NOTEBOOK = pathlib.Path(__file__).resolve().parents[2] / "examples" / "tuning.ipynb"


def test_the_tuning_notebook_runs():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    t = time.perf_counter()
    nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    ).execute()
    print(f"examples/tuning.ipynb ran in {time.perf_counter() - t:.1f} s")
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    text = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    assert "evaluations of" in text and "saturated or wrapped:" in text
    # Each of the three plots is drawn (a figure per plot in the cells' outputs).
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) == 3, len(images)


def test_the_tuning_bindings_agree_with_each_other():
    import tooltouch

    r = tooltouch.ranges(scenarios=1)
    assert r["format"] == "tooltouch-ranges-2"
    kinds = {x["name"]: x["kind"] for x in r["registers"]}
    for name in ["charge", "position", "override_pct", "force_estimate"]:
        assert kinds[name] == "output", name
    # The kernels' internal registers beside them: the sampling sums, the no-load sums,
    # the PI integrator inside its clamp, the glitch filters' counters.
    for name in ["sampler.sums[power]", "estimator.no_load.sww", "pi.integral", "glitch.stable[fes]"]:
        assert kinds[name] == "internal", name
    pi = next(x for x in r["registers"] if x["name"] == "pi.integral")
    assert pi["limits"] == [0.0, 255.0] and pi["format"] == "I32F32 clamp 0..255"
    assert 0.0 < pi["min"] <= pi["max"] < 255.0 and pi["saturations"] == 0
    n = next(x for x in r["registers"] if x["name"] == "estimator.no_load.n")
    assert n["max"] >= 10 and n["path"] == "force"
    try:
        tooltouch.tune_optimize('path = "measure"\n[constraints]\ndiameter_error_um = "a"\n')
    except ValueError as e:
        assert "constraints.diameter_error_um" in str(e)
    else:
        raise AssertionError("a malformed spec must be a ValueError")
