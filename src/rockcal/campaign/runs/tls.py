"""Reaching a Dask scheduler safely. Tasks and results are pickles, so whoever reaches a
scheduler can run code on its workers: a tls:// scheduler is reached with mutual TLS
(`distributed.Security`), its certificates from --tls-ca-file/--tls-cert/--tls-key or else from
the Dask config (distributed.comm.tls); tcp:// is for a network no one else is on."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rockcal.errors import InputError

OPTION = "--scheduler"
CLEAR_TEXT = ("%s carries runs and results unencrypted, and anyone who reaches the scheduler can "
              "run code on its workers; use tls:// with certificates (the docs' how-to: Secure a cluster with TLS)")


@dataclass(frozen=True)
class TLSFiles:
    """The client's certificates for a tls:// scheduler: the cluster's CA, this client's
    certificate and its key (None: in the certificate's file)."""

    ca_file: Path
    cert: Path
    key: Path | None = None


def tls_files(ca_file: Path | None, cert: Path | None, key: Path | None) -> TLSFiles | None:
    """The --tls-* options as TLSFiles (None when none is given); InputError naming the option
    that is missing or cannot be read."""
    given = {"--tls-ca-file": ca_file, "--tls-cert": cert, "--tls-key": key}
    if all(v is None for v in given.values()):
        return None
    for option in ("--tls-ca-file", "--tls-cert"):
        if given[option] is None:
            raise InputError(option, "needed with the other --tls-* options (mutual TLS)")
    for option, path in given.items():
        if path is not None and not Path(path).is_file():
            raise InputError(option, f"{path} is not a readable file")
    return TLSFiles(Path(ca_file), Path(cert), None if key is None else Path(key))


def security_of(kind: str, tls: TLSFiles | None):
    """The `distributed.Security` of a scheduler and where its certificates come from (None,
    "" for tcp:// and local:N); InputError for TLS files without tls://, or tls:// without
    certificates in the options or the Dask config."""
    from distributed import Security

    if tls is not None and kind != "tls":
        raise InputError("--tls-ca-file", "the --tls-* options are for a tls://HOST:PORT --scheduler")
    if kind != "tls":
        return None, ""
    if tls is not None:
        return Security(tls_ca_file=str(tls.ca_file), tls_client_cert=str(tls.cert),
                        tls_client_key=None if tls.key is None else str(tls.key),
                        require_encryption=True), "--tls-ca-file, --tls-cert and --tls-key"
    security = Security(require_encryption=True)
    if not (security.tls_ca_file and security.tls_client_cert):
        raise InputError(OPTION, "tls:// needs the cluster's certificates: give --tls-ca-file, "
                                 "--tls-cert and --tls-key, or set distributed.comm.tls.ca-file, "
                                 ".client.cert and .client.key in the Dask config")
    return security, "the Dask config (distributed.comm.tls)"
