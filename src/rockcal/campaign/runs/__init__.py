"""The forward runs: executed on a process pool (`pool`) or a Dask cluster (`dask`, with TLS:
`tls`), chosen by `executors`; stored by key (`store`) by one writer at a time (`lock`), and
failed runs tried again (`retries`)."""
