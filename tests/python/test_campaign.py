"""sets.campaign: a small Farah study on a LocalCluster of 2 workers equals the serial run for
the same seeds, and both equal what sets-ss-uncertainty writes for the same settings."""

import json

import pytest

import sets.campaign as sc

TIMING = ("seconds", "cpu_seconds")


def without_timing(j):
    j = {k: v for k, v in j.items() if k not in TIMING}
    j["settings"] = {k: v for k, v in j["settings"].items() if k != "threads"}
    return j


@pytest.fixture(scope="module")
def study():
    return sc.FarahStudy(runs=12, seed=3, samples=300, past=10)


@pytest.fixture(scope="module")
def serial(study):
    return sc.run_study(study, serial=True)


def test_local_cluster_with_two_workers_equals_serial(study, serial):
    client = sc.local_client(workers=2)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        merged = sc.run_study(study, client=client, chunk=5)  # 3 tasks of 5, 5 and 2 runs
        # the scale-out path: a new client of a running scheduler, by its address
        by_address = sc.run_study(study, scheduler=client.scheduler.address, chunk=4)
        assert len(client.scheduler_info()["workers"]) == 2, "run_study(scheduler=...) must not stop the cluster"
    finally:
        client.close()
        client.cluster.close()
    assert merged["settings"]["threads"] == 2 and by_address["settings"]["threads"] == 2
    assert without_timing(merged) == without_timing(serial)
    assert without_timing(by_address) == without_timing(serial)
    json.dumps(merged)  # plain JSON


def test_serial_study_equals_the_app(study, serial, app, tmp_path):
    app("sets-ss-uncertainty", "--runs", study.runs, "--seed", study.seed, "--samples", study.samples, "--past",
        study.past, "--threads", 2, "--no-guaranteed", "--json", tmp_path / "farah.json")
    expected = json.loads((tmp_path / "farah.json").read_text())
    assert set(serial) == set(expected)
    assert set(serial["settings"]) == set(expected["settings"])
    assert serial["failure_rates"] == expected["failure_rates"]  # counts of runs: exact
    for got, want in zip(serial["parameters"], expected["parameters"]):
        assert got["name"] == want["name"] and got["true"] == want["true"]
        # mean and std: the same runs, summed in another order (numpy vs Eigen)
        assert got["mean"] == pytest.approx(want["mean"], rel=1e-12, abs=1e-15)
        assert got["std"] == pytest.approx(want["std"], rel=1e-9, abs=1e-15)
    for key in ("seed", "snr_db", "past", "samples", "estimate_d", "residuals", "norm", "level_factor", "mean_ell",
                "pui_runs", "noise", "noise_bound_sigmas"):
        assert serial["settings"][key] == expected["settings"][key], key


def test_diagnosis_suite_task_gives_the_json_of_sets_diagnose():
    suite = sc.DiagnosisSuite(plants=["coulomb_friction"])
    merged = sc.run_study(suite, serial=True)
    assert merged["total"] == 1 and merged["named_right"] == 1
    assert merged["plants"][0]["diagnosis"]["effects"][0]["name"] == "coulomb_friction"
