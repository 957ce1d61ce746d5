"""One way to get Dask workers, for every parallel run of the project (the catalog's
validation, the direction sweep): an existing scheduler by address, else a local cluster
of ``jobs`` single-threaded worker processes (default one per core)."""
from __future__ import annotations

import os
from contextlib import contextmanager


@contextmanager
def dask_client(jobs: int | None = None, scheduler: str | None = None):
    """Yield a ``dask.distributed.Client``; a local cluster is closed on exit. Its dashboard takes
    a free port (":0"), so a second cluster on the machine prints no port warning."""
    from dask.distributed import Client, LocalCluster

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        n = jobs or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                               silence_logs=40)
        client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
