"""The sweeps' parallel map: each job is a `tactile_sim` process, so threads suffice."""
import concurrent.futures


def pmap(fn, jobs, workers):
    """Yields (k, n, fn(job)) for k = 1..n in the jobs' order, running up to
    `workers` at once."""
    jobs = list(jobs)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, workers)) as ex:
        for k, r in enumerate(ex.map(fn, jobs), 1):
            yield k, len(jobs), r
