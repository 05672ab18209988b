#!/bin/bash
# The 16-core scale-out figure of issue 37 (benchmarks/bench_parallel.py), as one script for a
# lent machine that reaches no package index: lmidsl built from this tree, and the distributions that
# machine lacks from wheels carried in .whl/ (clarabel, python-flint, dask, distributed, tornado,
# zict, tblib, partd, locket: `pip download --no-deps --only-binary=:all:` of constraints.txt's
# versions for its Python); numpy, scipy, sympy, rich, cloudpickle, msgpack, psutil are its own.
# Writes bench.txt and bench.json to $OUT (or to the current folder).
set -o pipefail
OUT=${OUT:-.}
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 3
python3 -m pip install -q --no-index --no-deps --no-build-isolation --no-cache-dir --target /tmp/site . || exit 3
export PYTHONPATH=/tmp/site PYTHONUNBUFFERED=1
python3 -c "import sys, numpy, scipy, sympy, flint, clarabel, dask, distributed, rich
print('python', sys.version.split()[0], 'numpy', numpy.__version__, 'scipy', scipy.__version__, 'sympy', sympy.__version__,
      'python-flint', flint.__version__, 'clarabel', clarabel.__version__, 'dask', dask.__version__)" || exit 3
lscpu | grep -iE "^model name|^cpu\(s\)|thread|core|socket|mhz" | tee $OUT/cpu.txt
# untimed: the theorem index cache and the byte-code of every module the runs import
python3 -m lmidsl sweep li_delay_dropout.thm2 --example paper --grid xi1=0.5 --grid xi2=0.5 >/dev/null || exit 3
python3 benchmarks/bench_parallel.py --grid 19 --runs 1 --counts ${COUNTS:-1,2,4,8,16} \
    --pool-counts ${POOL_COUNTS:-16} --cluster ${CLUSTER:-16} --small --json-out $OUT/bench.json 2>&1 | tee $OUT/bench.txt
