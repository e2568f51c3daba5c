"""Monte Carlo studies and diagnosis suites as independent tasks on a Dask cluster.

A study is a list of independent runs (each depends only on its index: its own random seed) and
a merge of their records into the JSON the app writes. ``run_study`` executes the runs

* on a ``distributed.LocalCluster`` (default: one single-threaded worker process per core),
* on an existing cluster given by its scheduler address (``scheduler="tcp://host:8786"``, see
  docs/scaling.md for dask-scheduler / dask-worker), or an existing ``client``,
* or serially in this process (``serial=True``),

and returns the same merged dict in every case: records are merged in run order, so the result
does not depend on where or in which order the runs were computed (timings aside).

    import sets.campaign as sc
    study = sc.FarahStudy(runs=1000, seed=1)
    result = sc.run_study(study)                 # LocalCluster on this machine
    json.dump(result, open("farah.json", "w"))   # the keys of sets-ss-uncertainty --json

Runs are sent in chunks (``chunk`` runs per task) to amortise the per-task overhead of Dask.
"""

import math
import os
import time

import numpy as _np

from . import _sets

__all__ = ["FarahStudy", "DiagnosisSuite", "run_study", "local_client"]


# ----------------------------------------------------------------------------- execution

def _run_chunk(study, indices):
    """One Dask task: the records of the runs `indices` plus the CPU seconds they took."""
    t0 = time.process_time()
    records = [study.run(i) for i in indices]
    return records, time.process_time() - t0


def local_client(workers=None, threads_per_worker=1):
    """A distributed.Client on a new LocalCluster of `workers` processes (default: the number of
    cores), no dashboard. Close it with client.close(); client.cluster.close()."""
    from distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=threads_per_worker,
                           processes=True, dashboard_address=None)
    return Client(cluster)


def run_study(study, client=None, scheduler=None, workers=None, chunk=None, serial=False, progress=None):
    """Runs every run of `study` and returns study.merge(...): the JSON-ready dict of the app.

    serial: in this process. client: an existing distributed.Client. scheduler: the address of a
    running dask-scheduler. Otherwise a LocalCluster of `workers` processes is started and closed.
    chunk: runs per task (default: about 8 tasks per worker). progress: callable(str) (default:
    print when the study has more than 50 runs)."""
    n = study.runs
    if progress is None:
        progress = print if n > 50 else (lambda s: None)
    wall0 = time.perf_counter()
    if serial:
        records, cpu = _run_chunk(study, range(n))
        return study.merge(records, time.perf_counter() - wall0, cpu, workers=1)
    own = client is None
    if own:
        if scheduler is not None:
            from distributed import Client
            client = Client(scheduler)
        else:
            client = local_client(workers)
    try:
        nworkers = max(1, len(client.scheduler_info().get("workers", {})) or (workers or 1))
        chunk = chunk or max(1, math.ceil(n / (8 * nworkers)))
        chunks = [list(range(k, min(n, k + chunk))) for k in range(0, n, chunk)]
        from distributed import as_completed
        study_future = client.scatter(study, broadcast=True)
        futures = [client.submit(_run_chunk, study_future, c, pure=False) for c in chunks]
        done, results = 0, {}
        for fut in as_completed(futures):
            records, cpu = fut.result()
            results[futures.index(fut)] = (records, cpu)
            done += len(records)
            progress("[campaign] %s: %d/%d runs" % (study.name, done, n))
        records = [r for k in range(len(chunks)) for r in results[k][0]]
        cpu = sum(results[k][1] for k in range(len(chunks)))
        return study.merge(records, time.perf_counter() - wall0, cpu, workers=nworkers)
    finally:
        if own:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and scheduler is None:
                cluster.close()


# ----------------------------------------------------------------------------- Farah et al.

_INSIDE, _OUTSIDE, _UNDECIDED = 0, 1, 2


def _verdict(b):
    return _INSIDE if b == _sets.BoolInterval.yes else _OUTSIDE if b == _sets.BoolInterval.no else _UNDECIDED


class FarahStudy:
    """The Monte Carlo study of Farah et al., Section V, as sets-ss-uncertainty runs it without
    --data --no-guaranteed: `runs` data sets of `samples` samples (random binary input, white
    Gaussian or uniform output noise at snr_db per channel), run k drawn from seed * 1000003 + k
    exactly as the app draws it; merge() gives the keys of `sets-ss-uncertainty --no-guaranteed
    --json` (Table I, failure rates, half-widths, settings). The app's guaranteed set (its
    default) is not in the Python study yet."""

    name = "farah"

    def __init__(self, runs=1000, seed=1, snr_db=20.0, past=20, samples=1000, estimate_d=False,
                 residuals="all", norm="entrywise", level_factor=2.0, fps_pui_runs=-1, noise="gaussian",
                 noise_bound_sigmas=4.0):
        self.runs, self.seed, self.snr_db, self.past, self.samples = runs, seed, snr_db, past, samples
        self.noise, self.noise_bound_sigmas = noise, noise_bound_sigmas
        self.estimate_d, self.residuals, self.norm = estimate_d, residuals, norm
        self.level_factor, self.fps_pui_runs = level_factor, fps_pui_runs

    # The structure is rebuilt in each process (cheap), never pickled.
    def _setup(self):
        if getattr(self, "_cache", None) is None:
            sys_ = _sets.examples.farah_system()
            rows = _sets.select_rows(sys_.A, sys_.C, _sets.RowSelection.output_major)
            structure = _sets.CanonicalStructure(rows, 2, 2, self.estimate_d)
            truth = structure.to_parameters(_sets.canonical_form(sys_, rows))
            m = len(truth)
            pairs = [(i, j) for i in range(m) for j in range(i + 1, m)]
            self._cache = (rows, structure, truth, pairs)
        return self._cache

    def __getstate__(self):
        d = dict(self.__dict__)
        d.pop("_cache", None)
        return d

    def _options(self, run):
        rows = self._setup()[0]
        level = _sets.LevelSetOptions(
            residuals=getattr(_sets.ResidualSelection, self.residuals),
            norm={"entrywise": _sets.ResidualNorm.entrywise, "sample": _sets.ResidualNorm.sample_euclidean,
                  "sample_euclidean": _sets.ResidualNorm.sample_euclidean,
                  "equation": _sets.ResidualNorm.per_equation, "per_equation": _sets.ResidualNorm.per_equation}[self.norm],
            level_factor=self.level_factor)
        ident = _sets.PropagatorOptions(order=3, past=self.past, estimate_d=self.estimate_d, rows=rows)
        return _sets.SsUncertaintyOptions(identification=ident, level=level,
                                          estimate_fps_pui=self.fps_pui_runs < 0 or run < self.fps_pui_runs)

    def run(self, k):
        rows, structure, truth, pairs = self._setup()
        u, y = _sets.examples.farah_data(self.samples, self.snr_db, (self.seed * 1000003 + k) % 2 ** 64,
                                         self.noise)
        res = _sets.ss_uncertainty(u, y, self._options(k))
        dom = res.estimate_level_set
        rec = {"run": k, "theta": list(dom.theta), "ell": dom.ell,
               "full": _verdict(_sets.contains(dom.ellipsoid, truth)),
               "fps_full": _verdict(res.estimate_fps.contains(truth)),
               "box_halfwidth": list(sets_radius(_sets.outer_box(dom.ellipsoid))),
               "projection": [], "slice": []}
        for i, j in pairs:
            v = _sets.pair_view(dom.ellipsoid, i, j)
            tp = _np.array([truth[i], truth[j]])
            rec["projection"].append(_verdict(_sets.contains(v.projection, tp)))
            rec["slice"].append(_verdict(_sets.contains(v.slice, tp)) if v.slice is not None else _OUTSIDE)
        p = res.estimate_fps_pui
        rec["pui_done"] = p is not None
        if p is not None:
            rec["fps_pui"] = _OUTSIDE if p.empty else (_INSIDE if p.box.contains(truth) else _OUTSIDE)
            rec["pui_halfwidth"] = [0.0] * len(truth) if p.empty else list(sets_radius(p.box))
        return rec

    def merge(self, records, seconds, cpu_seconds, workers=1):
        records = sorted(records, key=lambda r: r["run"])
        assert [r["run"] for r in records] == list(range(self.runs)), "missing or repeated runs"
        rows, structure, truth, pairs = self._setup()
        names = structure.parameter_names
        n, m = self.runs, len(truth)
        TH = _np.array([r["theta"] for r in records]).T
        mean = TH.mean(axis=1)
        sd = TH.std(axis=1, ddof=1) if n > 1 else _np.zeros(m)

        def rate(get):
            v = [get(r) for r in records]
            return sum(x == _OUTSIDE for x in v) / n

        order = [k for k, (i, j) in enumerate(pairs)
                 if (names[i], names[j]) in (("-a0", "-a1"), ("-a2", "b0^1"))]
        order += [k for k in range(len(pairs)) if k not in order]
        jpairs = [{"pair": [names[pairs[k][0]], names[pairs[k][1]]],
                   "projection": rate(lambda r, k=k: r["projection"][k]),
                   "slice": rate(lambda r, k=k: r["slice"][k])} for k in order]
        pui = [r for r in records if r["pui_done"]]
        ell_mean = 0.0
        for r in records:  # the app's summation order
            ell_mean += r["ell"] / n
        j = {"runs": n,
             "parameters": [{"name": names[i], "true": truth[i], "mean": mean[i], "std": sd[i]} for i in range(m)],
             "failure_rates": {"pairs": jpairs, "full": rate(lambda r: r["full"]),
                               "estimate_fps_full": rate(lambda r: r["fps_full"])}}
        if pui:
            j["failure_rates"]["estimate_fps_pui_box"] = sum(r["fps_pui"] == _OUTSIDE for r in pui) / len(pui)
        j["seconds"], j["cpu_seconds"] = seconds, cpu_seconds
        j["settings"] = {"seed": self.seed, "snr_db": self.snr_db, "past": self.past, "samples": self.samples,
                         "threads": workers, "estimate_d": self.estimate_d, "residuals": self.residuals,
                         "norm": _NORM_NAMES[self.norm],
                         "level_factor": self.level_factor, "mean_ell": ell_mean, "pui_runs": len(pui),
                         "noise": self.noise, "noise_bound_sigmas": self.noise_bound_sigmas}
        return _plain(j)


_NORM_NAMES = {"entrywise": "entrywise", "sample": "sample-euclidean", "sample_euclidean": "sample-euclidean",
               "equation": "per-equation", "per_equation": "per-equation"}


def sets_radius(box):
    return _np.asarray(box.radius)


# ----------------------------------------------------------------------------- diagnosis suite

class DiagnosisSuite:
    """The diagnosis of every synthetic plant (sets-diagnose --suite), one task per plant; merge()
    gives {"plants": [{"plant", "true_effect", "named", "right", "diagnosis": <the JSON of
    sets-diagnose --json>}, ...], "named_right": k, "total": n}."""

    name = "diagnosis suite"

    def __init__(self, plants=None, threads=1, noise_floor=True):
        self.plants = list(plants) if plants is not None else list(_sets.examples.synthetic_plant_names())
        self.runs = len(self.plants)
        self.threads, self.noise_floor = threads, noise_floor

    def run(self, k):
        from . import diagnose
        p = _sets.examples.synthetic_plant(self.plants[k])
        opts = _sets.DiagnosisOptions(threads=self.threads)
        if not self.noise_floor:
            opts.noise_floor_factor = 0.0
        d = diagnose(p.nominal, p.estimation, p.validation, options=opts)
        named = [e["name"] for e in d["effects"]]
        first = named[0] if named else "none"
        return {"run": k, "plant": p.name, "true_effect": p.true_effect, "named": named or ["none"],
                "right": first == p.true_effect, "diagnosis": dict(d)}

    def merge(self, records, seconds, cpu_seconds, workers=1):
        records = sorted(records, key=lambda r: r["run"])
        plants = [{k: v for k, v in r.items() if k != "run"} for r in records]
        return _plain({"plants": plants, "named_right": sum(r["right"] for r in records), "total": len(records),
                       "seconds": seconds, "cpu_seconds": cpu_seconds, "workers": workers})


def _plain(x):
    """numpy scalars and arrays -> Python numbers and lists (json.dump-able); NaN/inf -> None as
    the apps' JSON writes them."""
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, _np.ndarray):
        return [_plain(v) for v in x.tolist()]
    if isinstance(x, (_np.floating, float)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, _np.integer):
        return int(x)
    if isinstance(x, _np.bool_):
        return bool(x)
    return x


# ----------------------------------------------------------------------------- command line

def _noop(i):
    return i


def task_overhead(client, tasks=200):
    """Median wall seconds per task of `tasks` no-op tasks submitted together and gathered (the
    scheduling and transfer cost a study's chunk pays on top of its runs), over 3 repetitions."""
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        client.gather(client.map(_noop, range(tasks), pure=False))
        times.append((time.perf_counter() - t0) / tasks)
    return sorted(times)[1]


def main(argv=None):
    """python3 -m sets.campaign {farah,diagnosis} [--runs N] [--seed S] [--workers W | --scheduler ADDR
    | --serial] [--chunk C] [--json FILE] [--overhead]"""
    import argparse
    import json
    p = argparse.ArgumentParser(prog="python3 -m sets.campaign", description=__doc__.splitlines()[0])
    p.add_argument("study", choices=["farah", "diagnosis"], help="the Farah et al. Monte Carlo study or the diagnosis suite")
    p.add_argument("--runs", type=int, default=1000, help="Farah runs (default 1000)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--samples", type=int, default=1000, help="Farah samples per run")
    p.add_argument("--past", type=int, default=20, help="Farah past horizon")
    p.add_argument("--noise", choices=["gaussian", "uniform"], default="gaussian", help="Farah output noise")
    p.add_argument("--fps-pui-runs", type=int, default=-1, help="Farah: FPS PUIs in the first K runs (-1: all)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--serial", action="store_true", help="in this process")
    where.add_argument("--workers", type=int, help="LocalCluster of W worker processes (default: one per core)")
    where.add_argument("--scheduler", help="address of a running dask-scheduler, e.g. tcp://host:8786")
    p.add_argument("--chunk", type=int, help="runs per task (default: about 8 tasks per worker)")
    p.add_argument("--json", help="write the merged result here (the keys the app's --json writes)")
    p.add_argument("--overhead", action="store_true", help="also measure the per-task overhead of the cluster")
    a = p.parse_args(argv)
    if a.study == "farah":
        study = FarahStudy(runs=a.runs, seed=a.seed, samples=a.samples, past=a.past, fps_pui_runs=a.fps_pui_runs,
                           noise=a.noise)
    else:
        study = DiagnosisSuite()
    client = None
    if not a.serial:
        if a.scheduler:
            from distributed import Client
            client = Client(a.scheduler)
        else:
            client = local_client(a.workers)
    try:
        result = run_study(study, client=client, serial=a.serial, chunk=a.chunk)
        print("%s: %d runs, %.2f s wall, %.2f s CPU in the runs, %d worker(s)"
              % (study.name, study.runs, result["seconds"], result["cpu_seconds"],
                 result.get("workers", result.get("settings", {}).get("threads", 1))))
        if a.overhead and client is not None:
            print("per-task overhead (median of 3 x 200 no-op tasks): %.2f ms" % (1e3 * task_overhead(client)))
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None and not a.scheduler:
                cluster.close()
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)
    return 0


if __name__ == "__main__":
    # Run from the package module (not __main__) so that the workers unpickle the same classes.
    from sets.campaign import main as _main
    raise SystemExit(_main())
