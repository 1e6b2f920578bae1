#!/usr/bin/python3
"""Start-up cost of the command-line tool and of the Python module (run by `make bench` through
scripts/bench.sh, or `bench/startup_bench.py BUILD_DIR`). Targets of the issue: `uascma --version` <= 3 ms CPU,
`import uascma` <= 50 ms.

Prints
  version_cpu_ms   CPU time (user + system) per `uascma --version` process, the mean of RUNS runs, from the
                   kernel's accounting of this script's children (getrusage(RUSAGE_CHILDREN)): no shell counted;
  libraries        shared objects the tool maps at start (the lines of `ldd`, as the issue counted 55);
  import_cpu_ms    CPU time of `import uascma` alone in a fresh interpreter (time.process_time around it),
  import_wall_ms   and its wall time: the medians of RUNS interpreters (CPU time does not grow with the load of a
                   shared machine, wall time does).
"""
import os
import resource
import statistics
import subprocess
import sys

RUNS = int(os.environ.get("UASCMA_BENCH_STARTUP_RUNS", "50"))

IMPORT = """
import time
cpu, wall = time.process_time(), time.perf_counter()
import uascma
print((time.process_time() - cpu) * 1e3, (time.perf_counter() - wall) * 1e3)
"""


def children_cpu_s():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def version_cpu_ms(cli):
    subprocess.run([cli, "--version"], check=True, stdout=subprocess.DEVNULL)  # warm the page cache
    before = children_cpu_s()
    for _ in range(RUNS):
        subprocess.run([cli, "--version"], check=True, stdout=subprocess.DEVNULL)
    return (children_cpu_s() - before) / RUNS * 1e3


def library_count(cli):
    out = subprocess.run(["ldd", cli], check=True, capture_output=True, text=True).stdout
    return len([line for line in out.splitlines() if line.strip()])


def import_ms(python_dir):
    env = dict(os.environ, PYTHONPATH=python_dir, PYTHONDONTWRITEBYTECODE="1")
    cpu, wall = [], []
    for _ in range(RUNS):
        out = subprocess.run(["/usr/bin/python3", "-c", IMPORT], check=True, capture_output=True, text=True, env=env)
        c, w = (float(x) for x in out.stdout.split())
        cpu.append(c)
        wall.append(w)
    return statistics.median(cpu), statistics.median(wall)


def main():
    build = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build")
    cli = os.path.join(build, "uascma")
    print(f"uascma --version: {version_cpu_ms(cli):.2f} ms CPU per run ({RUNS} runs; target <= 3 ms)")
    print(f"uascma maps {library_count(cli)} shared libraries at start (ldd; 55 with MPI and PROJ linked)")
    mpi = os.path.join(build, "uascma-mpi")
    if os.path.exists(mpi):
        print(f"uascma-mpi (what mpirun runs) maps {library_count(mpi)} shared libraries at start")
    python_dir = os.path.join(build, "python")
    if os.path.isfile(os.path.join(python_dir, "uascma", "__init__.py")):
        cpu, wall = import_ms(python_dir)
        print(f"import uascma: {cpu:.1f} ms CPU, {wall:.1f} ms wall (medians of {RUNS}; target <= 50 ms)")


if __name__ == "__main__":
    main()
