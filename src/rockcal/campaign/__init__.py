"""A calibration campaign, one package per job: `input` reads the campaign file (targets,
settings, the embedded rocks' files), `procedure` is the inverse procedure (its steps, the
points they run, the final runs, the verdict and the result), `plan` prices a campaign before
it runs (the first screen, the engine's speed, the specimens' sizes), `runs` executes and
stores the forward runs (run specs and keys, the process pool, Dask and TLS, retries, the store
and its lock), `outputs` writes what a user keeps (the report, its figures, the PFC export),
and `files` keeps files whole and errors on them to one line."""
