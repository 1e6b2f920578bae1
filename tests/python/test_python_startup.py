"""Start-up of the Python module: ``import uascma`` maps neither libmpi nor libproj (the
compiled core links no MPI, and loads PROJ only when a map is projected), read from the process's own
/proc/self/maps. Timing is a benchmark (bench/startup_bench.py), not a test."""
import subprocess
import sys

MAPPED = """
import uascma
with open("/proc/self/maps") as f:
    names = {line.split()[-1].rsplit("/", 1)[-1] for line in f if "/" in line}
print(" ".join(sorted(names)))
"""


def mapped_after_import():
    return subprocess.run([sys.executable, "-c", MAPPED], capture_output=True, text=True, check=True).stdout.split()


def test_import_maps_neither_mpi_nor_proj():
    names = mapped_after_import()
    # The check sees the libraries the import did map: the compiled core and the C library.
    assert any(name.startswith("_uascma") for name in names), names
    assert any(name.startswith("libc.so") for name in names), names
    assert not [name for name in names if name.startswith(("libmpi", "libproj", "libopen-pal", "libcurl"))], names
