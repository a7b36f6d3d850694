"""--backend of the batch studies: the GPU is refused with a reason where it cannot run."""

from __future__ import annotations

from rotorcontact.studies import cuda_batch


def test_cli_refuses_cuda_with_workers_and_without_a_gpu(cli, tmp_path, monkeypatch):
    base = ("basins", "--gamma", "0.1", "--grid", "x=-0.5:0.5:2,y=0:0:1", "--out", tmp_path / "b.nc",
            "--no-progress")
    code, out, err = cli.run(*base, "--backend", "cuda", "--n-jobs", "2")
    assert code == 2 and "--backend cuda runs in this process on its GPU" in err and "Traceback" not in err
    monkeypatch.setattr(cuda_batch, "cuda_unavailable", lambda: "numba.cuda finds no usable CUDA GPU and driver")
    code, out, err = cli.run(*base, "--backend", "cuda")
    assert code == 2 and "--backend cuda cannot run here: numba.cuda finds no usable" in err and "Traceback" not in err
    assert not (tmp_path / "b.nc").exists() and not (tmp_path / "b.nc.chunks").exists()
    code, out, err = cli.run(*base, "--backend", "gpu")
    assert code == 2 and "invalid choice: 'gpu'" in err
