#!/usr/bin/env python3
"""Bake across machines on Dask distributed: one task per shard, retries, merge.

Each shard is a `baker … --shard I/N` process run by a Dask worker; its files go to a
folder every worker and this driver can read (a shared filesystem: NFS, Lustre, a
Kubernetes ReadWriteMany volume), or to an fsspec URL (s3://bucket/bake, gs://…,
memory://… for a cluster inside this process, file://…): then each task bakes in a
scratch folder of its worker, uploads every new checkpoint as it appears and the shard
file at the end, and a retry on any machine downloads the checkpoints first. A failed
shard (the process killed, the machine lost) is retried by Dask; the retry runs with
--resume, so it continues from the shard's last checkpoint, and the shard file it writes
is the same bytes either way. When every shard is in, the driver runs `baker merge OUT
SHARD…` (shard files fetched to a local folder first when they are remote; a remote OUT
is written locally and uploaded), which writes exactly the outputs of the single-machine
bake.

  # A local cluster of 3 worker processes on this machine:
  python dask_bake.py --shards 6 --local-workers 3 --shard-dir shards --out bake-out \
      -- --scene room.glb --passes 512
  # A running cluster (dask-jobqueue on Slurm, dask-kubernetes, `dask scheduler`):
  python dask_bake.py --scheduler tcp://head:8786 --shards 100 --shard-dir /shared/shards \
      --out /shared/bake-out -- --scene /shared/world.glb --passes 4096 --device gpu
  # No shared filesystem: shards through an object store (needs s3fs on every machine).
  python dask_bake.py --scheduler tcp://head:8786 --shards 100 --shard-dir s3://bakes/world/shards \
      --out s3://bakes/world/out -- --scene /local/world.glb --passes 4096 --device gpu

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


class Store:
    """Where the shard files and checkpoints live: a local folder (every worker sees it) or
    an fsspec URL (`scheme://…`, `file://` included), by file name."""

    def __init__(self, where):
        self.where = where
        self.remote = "://" in where
        if self.remote:
            import fsspec
            self.fs, self.root = fsspec.core.url_to_fs(where)
            self.fs.makedirs(self.root, exist_ok=True)
        else:
            self.root = os.path.abspath(where)
            os.makedirs(self.root, exist_ok=True)

    def path(self, name):
        return f"{self.root.rstrip('/')}/{name}" if self.remote else os.path.join(self.root, name)

    def names(self, pattern):
        """Names in the store matching a glob pattern."""
        if self.remote:
            return sorted(p.rsplit("/", 1)[-1] for p in self.fs.glob(self.path(pattern)))
        import glob
        return sorted(os.path.basename(p) for p in glob.glob(self.path(pattern)))

    def head(self, name, n):
        try:
            if self.remote:
                with self.fs.open(self.path(name), "rb") as f:
                    return f.read(n)
            with open(self.path(name), "rb") as f:
                return f.read(n)
        except (OSError, FileNotFoundError):
            return b""

    def get(self, name, local):
        self.fs.get(self.path(name), local)

    def put(self, local, name):
        self.fs.put(local, self.path(name))

    def write_text(self, name, text):
        with self.fs.open(self.path(name), "w") as f:
            f.write(text)


def checkpoint_passes(store, name):
    """Passes recorded in a baker checkpoint (magic 8 bytes, fingerprint u64, passes u64)."""
    head = store.head(name, 24)
    if len(head) < 24 or not head.startswith(b"SBFBAKE"):
        return None
    return struct.unpack("<Q", head[16:24])[0]


def run_shard(baker, args, index, count, where, checkpoint_every, threads, cancel=None):
    """A Dask task: bakes shard `index` of `count` into the store `where`; raises if the
    process fails. `cancel`: the name of a Dask Event the driver sets to stop every bake
    (the process is terminated, checked every 0.5 s)."""
    store = Store(where)
    tag = f"shard-{index}-of-{count}"
    record = f"{platform.node()} pid {os.getpid()} at {time.time():.3f}\n"
    if store.remote:
        # One object per attempt: object stores have no append.
        store.write_text(f"{tag}.attempt-{uuid.uuid4().hex}", record)
        out = tempfile.mkdtemp(prefix=f"sbf-{tag}-")
        # What an earlier attempt on any machine left: its checkpoints and the spec.
        for name in store.names(f"*.{tag}.checkpoint") + store.names("spec.json"):
            store.get(name, os.path.join(out, name))
    else:
        with open(store.path(f"{tag}.attempts"), "a") as f:
            f.write(record)
        out = store.root
    # --exit-with-parent: a killed worker takes its bake with it, so the retry does not race
    # an orphan over the same shard folder.
    cmd = [baker, *args, "--shard", f"{index}/{count}", "--out", out, "--resume",
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
    uploaded = {}

    def upload(names):
        # Checkpoints are renamed into place whole, so a file read here is a whole one.
        for name in names:
            local = os.path.join(out, name)
            try:
                st = os.stat(local)
            except OSError:
                continue
            if uploaded.get(name) != (st.st_mtime_ns, st.st_size):
                store.put(local, name)
                uploaded[name] = (st.st_mtime_ns, st.st_size)

    def checkpoints():
        return [n for n in os.listdir(out) if n.endswith(f".{tag}.checkpoint")]

    try:
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
                if store.remote:
                    upload(checkpoints())
                time.sleep(0.5)
            err.seek(0)
            p = subprocess.CompletedProcess(cmd, proc.returncode, None, err.read())
        if store.remote:
            upload(checkpoints())
        if p.returncode != 0:
            tail = "\n".join(p.stderr.strip().splitlines()[-5:])
            raise RuntimeError(f"shard {index}/{count}: baker exited with {p.returncode}\n{tail}")
        if store.remote:
            upload(["spec.json", f"{tag}.sbfshard"])
    finally:
        if store.remote:
            shutil.rmtree(out, ignore_errors=True)
    # "lightmap: resuming from … at pass P" when a retry continued from a checkpoint.
    resumed = [int(line.rsplit(" ", 1)[1]) for line in p.stderr.splitlines()
               if line.startswith("lightmap: resuming from ") and line.rsplit(" ", 1)[1].isdigit()]
    return index, time.time() - t, (resumed[0] if resumed else None)


def attempts_of(store, index, count):
    tag = f"shard-{index}-of-{count}"
    if store.remote:
        return len(store.names(f"{tag}.attempt-*"))
    try:
        with open(store.path(f"{tag}.attempts")) as f:
            return sum(1 for _ in f)
    except OSError:
        return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], epilog="Arguments after -- go to every baker shard.")
    ap.add_argument("--baker", default=shutil.which("baker") or "baker", help="the baker binary, as the workers see it")
    ap.add_argument("--shards", type=int, required=True, help="N: the bake is split into N shards")
    ap.add_argument("--shard-dir", required=True,
                    help="where shard files and checkpoints go: a folder workers and driver share, or an fsspec URL (s3://…, memory://…)")
    ap.add_argument("--out", required=True, help="the merged bake's output folder, or an fsspec URL it is uploaded to")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    ap.add_argument("--local-workers", type=int, default=0, help="start a local cluster of this many worker processes instead")
    ap.add_argument("--local-in-process", action="store_true",
                    help="the local cluster's workers as threads of this process (a memory:// store is then shared)")
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
    store = Store(a.shard_dir)
    where = a.shard_dir if store.remote else store.root

    from dask.distributed import Client, LocalCluster, as_completed

    t0 = time.time()
    if a.local_workers:
        threads = a.threads or max(1, (os.cpu_count() or 1) // a.local_workers)
        cluster = LocalCluster(n_workers=a.local_workers, threads_per_worker=1, processes=not a.local_in_process,
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
        f = client.submit(run_shard, baker, args, i, n, where, a.checkpoint_every, threads, cancel_name,
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
                k = attempts_of(store, i, n)
                retried = f", after {k - 1} retr{'y' if k == 2 else 'ies'}" if k > 1 else ""
                at = f", resumed at pass {resumed}" if resumed is not None else ""
                print(f"shard {i}/{n}: done in {secs:.1f} s (attempt {k}{retried}{at})", flush=True)
            else:
                failed[i] = f.exception()
                print(f"shard {i}/{n}: failed after {attempts_of(store, i, n)} attempts: {failed[i]}", flush=True)
        for i in range(n):
            if i in done or i in failed:
                continue
            k = attempts_of(store, i, n)
            if k != seen_attempts.get(i, 0):
                seen_attempts[i] = k
                print(f"shard {i}/{n}: attempt {k} started" + (" (retry: resumes from its checkpoint)" if k > 1 else ""), flush=True)
            p = checkpoint_passes(store, f"lightmap.shard-{i}-of-{n}.checkpoint")
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
    names = [f"shard-{i}-of-{n}.sbfshard" for i in range(n)]
    t_merge = time.time()
    with tempfile.TemporaryDirectory(prefix="sbf-merge-") as tmp:
        if store.remote:
            for name in names:
                store.get(name, os.path.join(tmp, name))
            shard_files = [os.path.join(tmp, name) for name in names]
        else:
            shard_files = [store.path(name) for name in names]
        out_remote = "://" in a.out
        # A remote output: merged into a local folder (which must not exist yet), uploaded.
        out = os.path.join(tmp, "out") if out_remote else a.out
        m = subprocess.run([baker, "merge", out, *shard_files], stderr=subprocess.PIPE, text=True)
        if m.returncode != 0:
            print(f"driver: merge failed:\n{m.stderr}", file=sys.stderr)
            return m.returncode
        if out_remote:
            import fsspec
            fs, root = fsspec.core.url_to_fs(a.out)
            fs.makedirs(root, exist_ok=True)
            for name in sorted(os.listdir(out)):
                local = os.path.join(out, name)
                fs.put(local, f"{root.rstrip('/')}/{name}", recursive=os.path.isdir(local))
    print(f"driver: merged {n} shards into {a.out} in {time.time() - t_merge:.1f} s; "
          f"wall {time.time() - t0:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
