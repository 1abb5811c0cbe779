#!/usr/bin/env python3
"""Bake across machines on Dask distributed: one task per shard, retries, merge.

Each shard is a `baker … --shard I/N` process run by a Dask worker; its files go to a
folder every worker and this driver can read (a shared filesystem: NFS, Lustre, a
Kubernetes ReadWriteMany volume). A failed shard (the process killed, the machine lost)
is retried by Dask; the retry runs with --resume, so it continues from the shard's last
checkpoint, and the shard file it writes is the same bytes either way. When every shard
is in, the driver runs `baker merge OUT SHARD…`, which writes exactly the outputs of the
single-machine bake.

  # A local cluster of 3 worker processes on this machine:
  python dask_bake.py --shards 6 --local-workers 3 --shard-dir shards --out bake-out \
      -- --scene room.glb --passes 512
  # A running cluster (dask-jobqueue on Slurm, dask-kubernetes, `dask scheduler`):
  python dask_bake.py --scheduler tcp://head:8786 --shards 100 --shard-dir /shared/shards \
      --out /shared/bake-out -- --scene /shared/world.glb --passes 4096 --device gpu

Progress: a line per shard when it starts, when its checkpoint advances (passes done, read
from the checkpoint's header), when it fails and is retried, and when it is done.
"""

import argparse
import os
import platform
import signal
import tempfile
import uuid
import shutil
import struct
import subprocess
import sys
import time


def checkpoint_passes(path):
    """Passes recorded in a baker checkpoint (magic 8 bytes, fingerprint u64, passes u64)."""
    try:
        with open(path, "rb") as f:
            head = f.read(24)
    except OSError:
        return None
    if len(head) < 24 or not head.startswith(b"SBFBAKE"):
        return None
    return struct.unpack("<Q", head[16:24])[0]


def run_shard(baker, args, index, count, shard_dir, checkpoint_every, threads, cancel=None):
    """A Dask task: bakes shard `index` of `count`; raises if the process fails. `cancel`:
    the name of a Dask Event the driver sets to stop every bake (the process is terminated,
    checked every 0.5 s)."""
    attempts = os.path.join(shard_dir, f"shard-{index}-of-{count}.attempts")
    with open(attempts, "a") as f:
        f.write(f"{platform.node()} pid {os.getpid()} at {time.time():.3f}\n")
    # --exit-with-parent: a killed worker takes its bake with it, so the retry does not race
    # an orphan over the same shard folder.
    cmd = [baker, *args, "--shard", f"{index}/{count}", "--out", shard_dir, "--resume",
           "--checkpoint-every", str(checkpoint_every), "--exit-with-parent"]
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    t = time.time()
    event = None
    if cancel is not None:
        from dask.distributed import Event
        event = Event(cancel)
        if event.is_set():
            raise RuntimeError(f"shard {index}/{count}: cancelled by the driver")
    with tempfile.TemporaryFile(mode="w+") as err:
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=err, text=True)
        while proc.poll() is None:
            if event is not None and event.is_set():
                proc.terminate()
                try:
                    proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
                raise RuntimeError(f"shard {index}/{count}: cancelled by the driver")
            time.sleep(0.5)
        err.seek(0)
        p = subprocess.CompletedProcess(cmd, proc.returncode, None, err.read())
    if p.returncode != 0:
        tail = "\n".join(p.stderr.strip().splitlines()[-5:])
        raise RuntimeError(f"shard {index}/{count}: baker exited with {p.returncode}\n{tail}")
    # "lightmap: resuming from … at pass P" when a retry continued from a checkpoint.
    resumed = [int(line.rsplit(" ", 1)[1]) for line in p.stderr.splitlines()
               if line.startswith("lightmap: resuming from ") and line.rsplit(" ", 1)[1].isdigit()]
    return index, time.time() - t, (resumed[0] if resumed else None)


def attempts_of(shard_dir, index, count):
    try:
        with open(os.path.join(shard_dir, f"shard-{index}-of-{count}.attempts")) as f:
            return sum(1 for _ in f)
    except OSError:
        return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], epilog="Arguments after -- go to every baker shard.")
    ap.add_argument("--baker", default=shutil.which("baker") or "baker", help="the baker binary, as the workers see it")
    ap.add_argument("--shards", type=int, required=True, help="N: the bake is split into N shards")
    ap.add_argument("--shard-dir", required=True, help="folder for shard files and checkpoints, shared by workers and driver")
    ap.add_argument("--out", required=True, help="the merged bake's output folder")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    ap.add_argument("--local-workers", type=int, default=0, help="start a local cluster of this many worker processes instead")
    ap.add_argument("--retries", type=int, default=3, help="times a failed shard is retried (default 3)")
    ap.add_argument("--checkpoint-every", type=int, default=16, help="passes between a shard's checkpoints (a retry resumes there)")
    ap.add_argument("--threads", type=int, default=0, help="CPU threads per shard (default: cores / local workers; all on a cluster)")
    ap.add_argument("baker_args", nargs=argparse.REMAINDER)
    a = ap.parse_args(argv)
    args = a.baker_args[1:] if a.baker_args[:1] == ["--"] else a.baker_args
    for bad in ("--shard", "--out", "--resume", "--checkpoint-every"):
        if any(x == bad or x.startswith(bad + "=") for x in args):
            ap.error(f"{bad} is set by the driver; leave it out of the baker arguments")
    if a.shards < 1:
        ap.error("--shards must be at least 1")
    if bool(a.scheduler) == bool(a.local_workers):
        ap.error("give either --scheduler ADDRESS or --local-workers K")
    baker = os.path.abspath(a.baker) if os.path.exists(a.baker) else a.baker
    shard_dir = os.path.abspath(a.shard_dir)
    os.makedirs(shard_dir, exist_ok=True)

    from dask.distributed import Client, LocalCluster, as_completed

    t0 = time.time()
    if a.local_workers:
        threads = a.threads or max(1, (os.cpu_count() or 1) // a.local_workers)
        cluster = LocalCluster(n_workers=a.local_workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    else:
        threads, cluster = a.threads, None
        client = Client(a.scheduler)
    n = a.shards
    # SIGTERM or SIGINT: set the cancel event (each running bake is terminated within a
    # second), then close the cluster; nothing is merged.
    from dask.distributed import Event
    cancel_name = f"sbf-cancel-{uuid.uuid4().hex}"
    cancel = Event(cancel_name, client=client)
    stop = []
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, lambda signum, _frame: stop.append(signum))
    print(f"driver: {n} shards on {len(client.scheduler_info()['workers'])} workers, "
          f"{a.retries} retries each", flush=True)
    futures = {}
    for i in range(n):
        f = client.submit(run_shard, baker, args, i, n, shard_dir, a.checkpoint_every, threads, cancel_name,
                          key=f"shard-{i}-of-{n}", pure=False, retries=a.retries)
        futures[f] = i
    done, failed = {}, {}
    seen_passes, seen_attempts = {}, {}
    pending = as_completed(list(futures))
    while len(done) + len(failed) < n:
        if stop:
            print(f"driver: signal {stop[0]}: cancelling the bakes; nothing merged", file=sys.stderr, flush=True)
            cancel.set()
            t_stop = time.time()
            while any(f.status == "pending" for f in futures) and time.time() - t_stop < 10:
                time.sleep(0.1)
            client.cancel(list(futures), force=True)
            client.close()
            if cluster is not None:
                cluster.close()
            return 128 + stop[0]
        for f in pending.next_batch(block=False) if pending.has_ready() else []:
            i = futures[f]
            if f.status == "finished":
                _, secs, resumed = f.result()
                done[i] = secs
                k = attempts_of(shard_dir, i, n)
                retried = f", after {k - 1} retr{'y' if k == 2 else 'ies'}" if k > 1 else ""
                at = f", resumed at pass {resumed}" if resumed is not None else ""
                print(f"shard {i}/{n}: done in {secs:.1f} s (attempt {k}{retried}{at})", flush=True)
            else:
                failed[i] = f.exception()
                print(f"shard {i}/{n}: failed after {attempts_of(shard_dir, i, n)} attempts: {failed[i]}", flush=True)
        for i in range(n):
            if i in done or i in failed:
                continue
            k = attempts_of(shard_dir, i, n)
            if k != seen_attempts.get(i, 0):
                seen_attempts[i] = k
                print(f"shard {i}/{n}: attempt {k} started" + (" (retry: resumes from its checkpoint)" if k > 1 else ""), flush=True)
            p = checkpoint_passes(os.path.join(shard_dir, f"lightmap.shard-{i}-of-{n}.checkpoint"))
            last = seen_passes.get(i, (None, 0.0))
            # At most one progress line per shard every 2 s.
            if p is not None and p != last[0] and time.time() - last[1] >= 2.0:
                seen_passes[i] = (p, time.time())
                print(f"shard {i}/{n}: {p} lightmap passes checkpointed", flush=True)
        time.sleep(0.05)
    client.close()
    if cluster is not None:
        cluster.close()
    if failed:
        print(f"driver: {len(failed)} shard(s) failed for good: {sorted(failed)}; nothing merged", file=sys.stderr)
        return 1
    shard_files = [os.path.join(shard_dir, f"shard-{i}-of-{n}.sbfshard") for i in range(n)]
    t_merge = time.time()
    m = subprocess.run([baker, "merge", a.out, *shard_files], stderr=subprocess.PIPE, text=True)
    if m.returncode != 0:
        print(f"driver: merge failed:\n{m.stderr}", file=sys.stderr)
        return m.returncode
    print(f"driver: merged {n} shards into {a.out} in {time.time() - t_merge:.1f} s; "
          f"wall {time.time() - t0:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
