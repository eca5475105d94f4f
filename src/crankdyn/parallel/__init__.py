"""Work beside the main process: a time-limited process pool and Dask for many variants
(:mod:`crankdyn.parallel.pool`) and the fork helpers that run one function in a child
(:mod:`crankdyn.parallel.fork`)."""
