"""``lmidsl cluster start|status|stop``: a Dask cluster on this machine kept across commands.

``start`` prints the scheduler's address (alone on stdout, so ``SCHED=$(lmidsl cluster start)``
works); later commands take it with ``--scheduler ADDRESS`` and start nothing
(:mod:`lmidsl.studies.cluster`)."""
from __future__ import annotations

import sys

from ..errors import InputError
from ..studies import cluster
from ..studies.parallel import usable_cores
from .common import positive_int, print_json

ORDER = 90


def register(sub):
    p = sub.add_parser("cluster", help="start, show or stop a Dask cluster kept across commands")
    p.add_argument("action", choices=("start", "status", "stop"))
    p.add_argument("--workers", type=positive_int, help="start: worker processes, one thread each "
                   "(default: one per usable core)")
    p.add_argument("--host", default="127.0.0.1", help="start: the address to listen on "
                   "(default 127.0.0.1, this machine only; 0.0.0.0 for workers on other machines)")
    p.add_argument("--port", type=int, default=0, help="start: the scheduler's port (default: a free one)")
    p.add_argument("--state", metavar="FILE", help="the state file (default: cluster.json in "
                   "lmidsl's cache folder)")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.set_defaults(run=run)


def run(args):
    if args.action == "start":
        record = cluster.start(args.workers or usable_cores(), args.host, args.port, args.state)
        if args.json:
            print_json(record)
        else:
            print(record["address"])
            print(f"{record['workers']} workers ready; use it with --scheduler {record['address']}; "
                  f"`lmidsl cluster stop` ends it (log: {record['log']})", file=sys.stderr)
        return 0
    if args.action == "status":
        record = cluster.status(args.state)
        if record is None:
            raise InputError(f"cluster status: no cluster recorded in {cluster.state_path(args.state)}")
        if args.json:
            print_json(record)
        else:
            print(record["address"])
            print(f"{record['workers_joined']} workers ({record['threads']} threads) joined"
                  if record["reachable"] else "not answering (`lmidsl cluster stop` forgets it)", file=sys.stderr)
        return 0 if record["reachable"] else 1
    record = cluster.stop(args.state)
    if record is None:
        raise InputError(f"cluster stop: no cluster recorded in {cluster.state_path(args.state)}")
    print(f"stopped the cluster at {record['address']}", file=sys.stderr)
    return 0
