"""The forward runs: executed on a process pool (`pool`) or a Dask cluster (`dask`, with TLS:
`tls`), chosen by `executors`; stored by key (`store`) by one writer at a time (`lock`), and
failed runs tried again (`retries`)."""

MAX_WORKERS = 256  # worker processes on one machine (--workers, local:N), each holding a specimen
