"""The GPU backend: its kernel through numba's CUDA simulator (no GPU needed), and its refusals.

The simulator runs the kernel's threads on the CPU's arithmetic, so there the backend must give the CPU
kernel's results bit for bit, contact phases and items handed back to the CPU included. It is switched on by an environment variable read
when numba is imported, hence a separate process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.cli.scale import BACKEND_CHOICES
from rotorcontact.studies import cuda_batch
from rotorcontact.studies.execution import BACKENDS, backend_manifest, make_executor

TESTS = Path(__file__).resolve().parents[1]

SIMULATED = textwrap.dedent("""
    import json
    import numpy as np
    from reference_parameters import REF
    from rotorcontact.studies.basins import basins, displacement_grid
    from rotorcontact.studies.batch import BatchSettings, parameter_array, run_lanes
    from rotorcontact.studies import cuda_batch
    from rotorcontact.studies.cuda_batch import cuda_unavailable, run_lanes_cuda

    out = {"unavailable": cuda_unavailable()}
    # independent items: impacting, contact-free and rubbing ones
    grid = displacement_grid((-0.9, 0.9, 4), (-0.9, 0.9, 4))
    cpu = basins(REF.replace(gamma=0.1), grid, progress=False, n_transient=300, n_record=40, settle=25)
    gpu = basins(REF.replace(gamma=0.1), grid, progress=False, n_transient=300, n_record=40, settle=25,
                 backend="cuda")
    out["fractions"] = cpu.fractions
    out["handed_to_cpu"] = gpu.handed_to_cpu
    # the command line says what ran where
    import contextlib, io
    from rotorcontact.cli.main import main
    text, notes = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(text), contextlib.redirect_stderr(notes):
        code = main(["basins", "--gamma", "0.1", "--grid", "x=-0.9:0.9:4,y=-0.9:0.9:4", "--transient", "300",
                     "--record", "40", "--settle", "25", "--out", "b.nc", "--backend", "cuda", "--json",
                     "--no-progress"])
    out["cli"] = [code, json.loads(text.getvalue()), notes.getvalue()]
    out["same_image"] = bool(np.array_equal(cpu.image, gpu.image))
    names = [n for n in cpu.dataset.data_vars if n != "attractor"]
    out["backend_attr"] = [gpu.dataset.attrs.get("backend"), cpu.dataset.attrs.get("backend")]
    out["same_data"] = all(cpu.dataset[n].values.tobytes() == gpu.dataset[n].values.tobytes() for n in names)
    # carried lanes from impacts into contact, with a short section
    settings = BatchSettings(n_transient=150, n_record=40, settle=25, n_keep=6)
    params = np.array([[parameter_array(REF.replace(gamma=g)) for g in (0.1, 0.08, 0.06, 0.05)]] * 2)
    u0 = np.zeros(params.shape[:2], complex)
    sec, summ, deferred = run_lanes_cuda(params, u0, u0, settings, carry=True)
    ref_sec, ref_summ = run_lanes(params, u0, u0, settings, carry=True)
    out["carried_deferred"] = deferred.tolist()
    out["carried_contacts"] = summ[:, -1, 6].tolist()
    out["carried_same"] = bool(np.array_equal(sec, ref_sec, equal_nan=True)
                               and np.array_equal(summ, ref_summ, equal_nan=True))
    # a lane the GPU hands back at its third step is finished by the CPU kernel from the state the GPU
    # reached there
    gpu_part = cuda_batch.launch_lanes

    def handing_back(params, u0, du0, settings, *, carry):
        sections, summary, deferred, start_u, start_du = gpu_part(params, u0, du0, settings, carry=carry)
        sections[0, 2:] = summary[0, 2:] = -7.0
        deferred[0] = 2
        start_u[0] = complex(summary[0, 1, 9], summary[0, 1, 10])
        start_du[0] = complex(summary[0, 1, 11], summary[0, 1, 12])
        return sections, summary, deferred, start_u, start_du

    cuda_batch.launch_lanes = handing_back
    sec, summ, deferred = run_lanes_cuda(params, u0, u0, settings, carry=True)
    cuda_batch.launch_lanes = gpu_part
    out["handed_back"] = deferred.tolist()
    out["handed_back_same"] = bool(np.array_equal(sec, ref_sec, equal_nan=True)
                                   and np.array_equal(summ, ref_summ, equal_nan=True))
    # a sweep with the state carried up and down (chains of chunks), and attractors followed over a parameter
    from rotorcontact.studies.attractors import attractors
    from rotorcontact.studies.sweep import sweep

    def same(a, b):
        return all(a[n].values.tobytes() == b[n].values.tobytes() for n in a.data_vars)

    kw = dict(n_transient=150, n_record=30, chunk_size=2, progress=False)
    out["sweep_same"] = same(sweep(REF, "gamma", [0.05, 0.06, 0.08, 0.1], **kw).dataset,
                             sweep(REF, "gamma", [0.05, 0.06, 0.08, 0.1], backend="cuda", **kw).dataset)
    kw = dict(n_transient=120, n_record=40, lyapunov=False, progress=False)
    small = displacement_grid((-0.6, 0.6, 3), (0.0, 0.0, 1))
    out["attractors_same"] = same(attractors(REF, "gamma", [0.1, 0.15], small, **kw).dataset,
                                  attractors(REF, "gamma", [0.1, 0.15], small, backend="cuda", **kw).dataset)
    # the executor stacks chunks into one launch and counts the items it left to the CPU
    from rotorcontact.studies.execution import ChunkTask, CudaExecutor
    tasks = [ChunkTask(key=str(i), params=params[i:i + 1], u0=u0[i:i + 1], du0=u0[i:i + 1], carry=True,
                       settings=settings) for i in range(2)]
    import rotorcontact.studies.execution as execution

    launches = []
    launch = cuda_batch.run_lanes_cuda
    cuda_batch.run_lanes_cuda = lambda params, *a, **k: (launches.append(params.shape[0]), launch(params, *a, **k))[1]
    executor = CudaExecutor()
    results = dict(executor.run(tasks))
    out["executor_same"] = all(np.array_equal(results[i]["summary"], ref_summ[i:i + 1], equal_nan=True)
                               for i in range(2))
    out["executor_handed_to_cpu"] = executor.handed_to_cpu
    # launches are bounded by the bytes of their results: here one chunk each
    execution.CUDA_RESULT_BYTES = 1
    results = dict(CudaExecutor().run(tasks))
    out["bounded_same"] = all(np.array_equal(results[i]["summary"], ref_summ[i:i + 1], equal_nan=True)
                              for i in range(2))
    out["launches"] = launches
    # a kernel that cannot be compiled or launched is one error, not numba-cuda's traceback
    import rotorcontact.studies.cuda_kernel as cuda_kernel

    class Broken:
        def __getitem__(self, config):
            def launch(*args):
                raise OSError("libnvvm.so: cannot open" + chr(10) + "  shared object file")
            return launch

    cuda_kernel.lanes_kernel = Broken()
    try:
        launch(params, u0, u0, settings, carry=True)
    except RuntimeError as exc:
        out["broken"] = str(exc)
    print(json.dumps(out))
""")


def test_the_simulated_gpu_gives_the_cpu_kernels_results_bit_for_bit(tmp_path):
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", PYTHONPATH=os.pathsep.join(
        [str(TESTS), *filter(None, [os.environ.get("PYTHONPATH")])]))
    proc = subprocess.run([sys.executable, "-c", SIMULATED], capture_output=True, text=True, env=env,
                          cwd=tmp_path, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["unavailable"] is None
    # impacting and rubbing items, all on the simulated GPU
    assert {"B1,d", "forward-rub"} <= set(out["fractions"])
    assert out["same_image"] and out["same_data"]
    assert out["backend_attr"] == ["cuda", None]
    code, summary, notes = out["cli"]
    assert code == 0 and summary["backend"] == "cuda" and summary["handed_to_cpu"] == out["handed_to_cpu"]
    # a note counts the simulations handed to the CPU, when there are any
    assert (f"note: {out['handed_to_cpu']} simulations were computed on the CPU" in notes) == \
        (out["handed_to_cpu"] > 0)
    assert out["carried_same"] and min(out["carried_contacts"]) > 0
    assert out["handed_back"] == [2, out["carried_deferred"][1]] and out["handed_back_same"]
    handed = sum(4 - s for s in out["carried_deferred"] if s >= 0)
    assert out["executor_same"] and out["executor_handed_to_cpu"] == handed
    assert out["bounded_same"] and out["launches"] == [2, 1, 1]
    assert out["broken"] == ("the GPU kernel could not be compiled or launched (OSError: libnvvm.so: cannot open "
                             "shared object file)")
    assert out["sweep_same"] and out["attractors_same"]


def test_backend_names_and_manifest():
    assert BACKEND_CHOICES == BACKENDS == ("cpu", "cuda")
    # CPU studies keep the digests they had; GPU ones are told apart
    assert backend_manifest("cpu") == {} and backend_manifest("cuda") == {"backend": "cuda"}
    with pytest.raises(ParameterError, match=r"backend = 'gpu' is invalid; allowed: 'cpu', 'cuda'"):
        make_executor(backend="gpu")
    with pytest.raises(ParameterError, match=r"n_jobs = 2 .*invalid with it"):
        make_executor(2, backend="cuda")


def test_a_gpu_without_the_cuda_compiler_is_refused_with_the_reason(monkeypatch):
    from numba import cuda
    from numba.cuda.cudadrv import nvvm

    monkeypatch.setattr(cuda, "is_available", lambda: True)
    monkeypatch.setattr(nvvm, "is_available", lambda: False)
    reason = cuda_batch.cuda_unavailable()
    assert reason.startswith("numba.cuda finds no NVVM") and "numba-cuda[cu12]" in reason


def test_without_a_gpu_the_cuda_backend_is_refused_with_the_reason(monkeypatch):
    monkeypatch.setattr(cuda_batch, "cuda_unavailable", lambda: "numba.cuda finds no usable CUDA GPU and driver")
    with pytest.raises(ParameterError, match=r"backend = 'cuda' cannot run here: numba.cuda finds no usable CUDA "
                                             r"GPU.*allowed: 'cpu'.*rotorcontact\[cuda\]"):
        make_executor(backend="cuda")


def test_numpy_row_stack_is_given_back_where_numpy_removed_it(monkeypatch):
    """numba-cuda compiles its np.row_stack on first use; numpy 2.5 removed that alias of np.vstack."""
    from rotorcontact.studies.cuda_batch import restore_numpy_names

    monkeypatch.delattr(np, "row_stack", raising=False)
    assert not hasattr(np, "row_stack")
    restore_numpy_names()
    assert np.row_stack is np.vstack
    restore_numpy_names()  # a second call leaves it
    assert np.row_stack is np.vstack


def test_no_function_the_gpu_kernel_compiles_calls_itself():
    """numba-cuda cannot compile recursion (a recursive call is an unresolved reference to its code
    generator), and CI, without a GPU, runs the kernel only through the simulator, which compiles nothing:
    the kernel's call graph is checked here instead, through the compiled functions it names."""
    import types

    from rotorcontact.studies.compact_batch import compact_lane

    def callees(func):
        codes, names = [func.__code__], set()
        while codes:
            code = codes.pop()
            names.update(code.co_names)
            codes.extend(c for c in code.co_consts if isinstance(c, types.CodeType))
        found = (func.__globals__.get(name) for name in names)
        return {f.py_func for f in found if hasattr(f, "py_func")}

    graph, todo = {}, [compact_lane.py_func]
    while todo:
        func = todo.pop()
        if func not in graph:
            graph[func] = callees(func)
            todo.extend(graph[func])
    assert len(graph) > 20  # the lane's own functions, the simulator's and the contact phases'

    def reaches(start, goal):
        seen, todo = set(), list(graph[start])
        while todo:
            func = todo.pop()
            if func is goal:
                return True
            if func not in seen:
                seen.add(func)
                todo.extend(graph[func])
        return False

    assert [f.__qualname__ for f in graph if reaches(f, f)] == []
