"""A tls:// scheduler: a tiny campaign on a local cluster that speaks only mutual TLS, with
self-signed certificates made here, reached with --tls-* files or the Dask config; without the
cluster's certificates nothing connects."""

import datetime
import ipaddress
import sys

import pytest

pytest.importorskip("distributed")
x509 = pytest.importorskip("cryptography.x509")

import dask  # noqa: E402
from cryptography.hazmat.primitives import hashes, serialization  # noqa: E402
from cryptography.hazmat.primitives.asymmetric import ec  # noqa: E402
from cryptography.x509.oid import NameOID  # noqa: E402
from distributed import LocalCluster, Security  # noqa: E402

from rockcal.campaign.input.config import SpecimenSettings, parse_campaign  # noqa: E402
from rockcal.campaign.plan.planned import planned  # noqa: E402
from rockcal.campaign.runs.dask import DaskExecutor, parse_scheduler  # noqa: E402
from rockcal.campaign.runs.tls import TLSFiles  # noqa: E402
from rockcal.campaign.runs.spec import run_spec  # noqa: E402
from rockcal.campaign.procedure.steps import calibrate  # noqa: E402
from rockcal.campaign.runs.store import RunStore  # noqa: E402
from rockcal.cli.app import main  # noqa: E402
from rockcal.errors import InputError  # noqa: E402
from tiny import tiny_campaign

CAMPAIGN = tiny_campaign(samples=4, iterations=10, max_dem_runs=5)


def name(text: str):
    return x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, text)])


def certificate(subject: str, key, issuer: str, issuer_key, ca: bool):
    now = datetime.datetime.now(datetime.timezone.utc)
    builder = (x509.CertificateBuilder().subject_name(name(subject)).issuer_name(name(issuer))
               .public_key(key.public_key()).serial_number(x509.random_serial_number())
               .not_valid_before(now - datetime.timedelta(minutes=5))
               .not_valid_after(now + datetime.timedelta(days=1))
               .add_extension(x509.BasicConstraints(ca=ca, path_length=None), critical=True))
    if not ca:
        builder = builder.add_extension(x509.SubjectAlternativeName(
            [x509.DNSName("localhost"), x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]), critical=False)
    return builder.sign(issuer_key, hashes.SHA256())


def write_pki(folder, label: str) -> dict:
    """A CA and a certificate it signs for 127.0.0.1 (PEM files), named by `label`."""
    ca_key, key = ec.generate_private_key(ec.SECP256R1()), ec.generate_private_key(ec.SECP256R1())
    ca = certificate(f"{label} CA", ca_key, f"{label} CA", ca_key, True)
    cert = certificate(f"{label} node", key, f"{label} CA", ca_key, False)
    paths = {"ca": folder / f"{label}-ca.pem", "cert": folder / f"{label}-cert.pem", "key": folder / f"{label}-key.pem"}
    paths["ca"].write_bytes(ca.public_bytes(serialization.Encoding.PEM))
    paths["cert"].write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    paths["key"].write_bytes(key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                               serialization.NoEncryption()))
    return paths


@pytest.fixture(scope="module")
def pki(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pki")
    return write_pki(folder, "cluster"), write_pki(folder, "stranger")


@pytest.fixture(scope="module")
def tls_cluster(pki):
    p, _ = pki
    security = Security(tls_ca_file=str(p["ca"]), tls_scheduler_cert=str(p["cert"]), tls_scheduler_key=str(p["key"]),
                        tls_worker_cert=str(p["cert"]), tls_worker_key=str(p["key"]),
                        tls_client_cert=str(p["cert"]), tls_client_key=str(p["key"]), require_encryption=True)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, protocol="tls", host="127.0.0.1",
                      dashboard_address=None, security=security) as cluster:
        yield cluster


@pytest.mark.slow  # a campaign
def test_a_tiny_campaign_runs_on_a_tls_cluster(pki, tls_cluster, tmp_path):
    p, _ = pki
    address = tls_cluster.scheduler_address
    assert address.startswith("tls://127.0.0.1:")
    store = RunStore(tmp_path)
    executor = DaskExecutor(store, address, tls=TLSFiles(p["ca"], p["cert"], p["key"]))
    try:
        result = calibrate(planned(parse_campaign(CAMPAIGN, tmp_path)), executor)
    finally:
        executor.close()
    assert executor.security_source == "--tls-ca-file, --tls-cert and --tls-key"
    assert executor.executed == result.dem_runs == store.count() and not result.failed_runs


def test_the_dask_config_gives_the_certificates_too(pki, tls_cluster, tmp_path):
    p, _ = pki
    config = {"distributed.comm.tls.ca-file": str(p["ca"]), "distributed.comm.tls.client.cert": str(p["cert"]),
              "distributed.comm.tls.client.key": str(p["key"])}
    spec = run_spec("ucs", SpecimenSettings(rmin_mm=0.4, width_mm=8, height_mm=16), {"E_c": 17.0})
    with dask.config.set(config):
        executor = DaskExecutor(RunStore(tmp_path), tls_cluster.scheduler_address)
        try:
            assert executor.run([spec])[0].status == "ok"
        finally:
            executor.close()
    assert executor.security_source == "the Dask config (distributed.comm.tls)"


def test_without_the_clusters_certificates_nothing_connects(pki, tls_cluster, tmp_path, monkeypatch):
    from rockcal.campaign.runs import dask as dask_executor

    monkeypatch.setattr(dask_executor, "CONNECT_TIMEOUT_S", 3.0)
    _, stranger = pki
    address = tls_cluster.scheduler_address
    with pytest.raises(InputError, match="^--scheduler: tls:// needs the cluster's certificates"):
        DaskExecutor(RunStore(tmp_path / "none"), address)
    with pytest.raises(InputError, match=f"^--scheduler: cannot reach the Dask scheduler at {address}"):
        DaskExecutor(RunStore(tmp_path / "stranger"), address,
                     tls=TLSFiles(stranger["ca"], stranger["cert"], stranger["key"]))
    plain = address.replace("tls://", "tcp://")
    with pytest.raises(InputError, match="^--scheduler: cannot reach the Dask scheduler at tcp://"):
        DaskExecutor(RunStore(tmp_path / "plain"), plain)


def test_tls_schedulers_parse():
    assert parse_scheduler("tls://head-node:8786") == ("tls", "tls://head-node:8786")


@pytest.mark.parametrize("args, says", [
    (["--scheduler", "tls://127.0.0.1:8786", "--tls-cert", "{cert}"], "--tls-ca-file: needed with"),
    (["--scheduler", "tcp://127.0.0.1:8786", "--tls-ca-file", "{ca}", "--tls-cert", "{cert}"],
     "--tls-ca-file: the --tls-* options are for a tls://"),
    (["--tls-ca-file", "{ca}", "--tls-cert", "{cert}"], "--tls-ca-file: the --tls-* options are for"),
    (["--scheduler", "tls://127.0.0.1:8786", "--tls-ca-file", "{missing}", "--tls-cert", "{cert}"],
     "--tls-ca-file: "),
    (["--scheduler", "tls://127.0.0.1:8786"], "--scheduler: tls:// needs the cluster's certificates"),
])
def test_bad_tls_options_are_one_line_before_any_store(args, says, pki, tmp_path, monkeypatch, capsys):
    p, _ = pki
    (tmp_path / "campaign.toml").write_text(CAMPAIGN)
    names = {"ca": p["ca"], "cert": p["cert"], "missing": tmp_path / "missing.pem"}
    argv = ["rockcal", "calibrate", str(tmp_path / "campaign.toml"), "--out", str(tmp_path / "out"),
            *[a.format(**names) for a in args]]
    monkeypatch.setattr(sys, "argv", argv)
    with pytest.raises(SystemExit) as exit:
        main()
    stderr = capsys.readouterr().err
    assert exit.value.code == 2 and len(stderr.splitlines()) == 1, stderr
    assert stderr.startswith("rockcal: error: " + says), stderr
    assert not (tmp_path / "out").exists()
