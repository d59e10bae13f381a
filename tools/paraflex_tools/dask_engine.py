"""A Dask evaluation engine for paraflex's ``SOL OPTIMIZE`` studies.

``paraflex run study.dat --engine "python -m paraflex_tools.dask_engine [options]"`` hands
every batch of designs to this driver, which fans them out to Dask workers, each running
``paraflex evaluate`` on a chunk of designs, and streams the answers back as they complete
(the protocol: ``src/sequence/optimize_engine.rs``; docs/optimize.md, "Evaluation engines").

The cluster, by option (the deck does not change):

* ``--local N`` (default: one worker per core): a ``LocalCluster`` of N single-threaded
  worker processes on this machine;
* ``--scheduler ADDRESS``: an existing Dask scheduler (``dask scheduler`` + ``dask worker``
  on the cluster's nodes);
* ``--jobqueue KIND --jobs N [--cores C --memory M --queue Q --walltime T]``: a
  dask-jobqueue cluster (``slurm``, ``pbs``, ``sge``, ``lsf``) of N batch jobs.

Workers run the paraflex executable and read the deck at the absolute paths paraflex sends:
on a cluster, both must be on a file system the workers share, and ``--paraflex`` names the
executable on the workers if its path differs there. An evaluation is a pure function of the
design, so a worker's answer equals, bit for bit, what the study's own threads compute.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile


def evaluate_chunk(paraflex: str, deck: str, subcase: int, designs: list[list[float]]) -> list[str]:
    """The journal lines of ``designs`` evaluated by ``paraflex evaluate`` (runs on a worker).

    A failed ``paraflex evaluate`` (it refused the deck or the designs, or it crashed) fails
    each design of the chunk with its message: the study records them as failed evaluations.
    """
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(designs, f)
        batch = f.name
    try:
        run = subprocess.run(
            [paraflex, "evaluate", deck, "--designs", batch, "--subcase", str(subcase)],
            capture_output=True,
            text=True,
            check=False,
        )
    finally:
        os.unlink(batch)
    lines = [line for line in run.stdout.splitlines() if line.startswith("{")]
    if run.returncode == 0 and len(lines) == len(designs):
        # passed through as written: the values keep their bits
        return lines
    why = run.stderr.strip().splitlines()[-1:] or [f"exit status {run.returncode}"]
    message = f"paraflex evaluate on a Dask worker failed: {why[0]}"
    return [
        json.dumps({"design": d, "responses": None, "error": message, "seconds": 0.0})
        for d in designs
    ]


def make_client(args: argparse.Namespace):
    """The Dask client of the cluster the options ask for."""
    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        return Client(args.scheduler)
    if args.jobqueue:
        import dask_jobqueue

        kinds = {
            "slurm": dask_jobqueue.SLURMCluster,
            "pbs": dask_jobqueue.PBSCluster,
            "sge": dask_jobqueue.SGECluster,
            "lsf": dask_jobqueue.LSFCluster,
        }
        cluster = kinds[args.jobqueue](
            cores=args.cores,
            memory=args.memory,
            queue=args.queue,
            walltime=args.walltime,
            processes=args.cores,
        )
        cluster.scale(jobs=args.jobs)
        return Client(cluster)
    workers = args.local or os.cpu_count() or 1
    cluster = LocalCluster(
        n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
    )
    return Client(cluster)


def chunks(designs: list, size: int) -> list[list]:
    return [designs[i : i + size] for i in range(0, len(designs), size)]


def serve(args: argparse.Namespace, stdin=sys.stdin, stdout=sys.stdout) -> None:
    """Answers paraflex's batches until it closes the input (the protocol of
    ``src/sequence/optimize_engine.rs``)."""
    from dask.distributed import as_completed

    hello = json.loads(stdin.readline())
    paraflex = args.paraflex or hello["paraflex"]
    client = make_client(args)
    try:
        for line in stdin:
            if not line.strip():
                continue
            designs = json.loads(line)["designs"]
            futures = [
                client.submit(
                    evaluate_chunk, paraflex, hello["deck"], hello["subcase"], chunk, pure=False
                )
                for chunk in chunks(designs, args.chunk)
            ]
            for future in as_completed(futures):
                for answer in future.result():
                    stdout.write(answer + "\n")
                stdout.flush()
    finally:
        client.close()


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m paraflex_tools.dask_engine",
        description="Dask evaluation engine for paraflex SOL OPTIMIZE (paraflex run --engine)",
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument("--local", type=int, metavar="N", help="LocalCluster of N workers")
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler")
    where.add_argument(
        "--jobqueue", choices=["slurm", "pbs", "sge", "lsf"], help="a dask-jobqueue cluster"
    )
    p.add_argument("--jobs", type=int, default=1, help="jobqueue: batch jobs")
    p.add_argument("--cores", type=int, default=1, help="jobqueue: cores (workers) per job")
    p.add_argument("--memory", default="4GB", help="jobqueue: memory per job")
    p.add_argument("--queue", default=None, help="jobqueue: queue / partition")
    p.add_argument("--walltime", default="01:00:00", help="jobqueue: wall time per job")
    p.add_argument(
        "--chunk", type=int, default=1, help="designs per task (one paraflex evaluate each)"
    )
    p.add_argument("--paraflex", help="the paraflex executable on the workers")
    return p


def main() -> None:
    args = parser().parse_args()
    if args.chunk < 1:
        parser().error("--chunk must be at least 1")
    serve(args)


if __name__ == "__main__":
    main()
