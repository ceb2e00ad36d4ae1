#!/usr/bin/env bash
# One entry point for a fresh machine that has python3 and g++ (cmake comes from PyPI if missing):
#   ./dev.sh demo     set up, then record the demo (demo.rrd: a sheet folding onto itself)
#   ./dev.sh test     set up, then run the test suite
#   ./dev.sh bench    set up, then run the benchmarks (tables, report.md, plots, JSON in bench-results/)
#   ./dev.sh sanitize the test suite against a core built with AddressSanitizer and UBSan (its own
#                     .venv-san/ and build/sanitize/; about 15 minutes on 2 cores; not part of CI)
#   ./dev.sh tsan     the thread tests against a core built with ThreadSanitizer (its own .venv-tsan/
#                     and build/tsan/; about 8 minutes on 2 cores with the build; not part of CI)
# Set-up creates .venv/ and installs conecull into it (editable, so rebuilds are incremental).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
PY=${PYTHON:-python3}
VENV=.venv

make_venv() {
    [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -m pip --version >/dev/null 2>&1 && return
    rm -rf "$VENV"
    if ! "$PY" -m venv "$VENV" 2>/dev/null; then
        # Debian without python3-venv: a venv without pip, then pip's own wheel from PyPI.
        echo "python3 -m venv has no ensurepip here; bootstrapping pip from PyPI" >&2
        rm -rf "$VENV"
        "$PY" -m venv --without-pip "$VENV"
        "$VENV/bin/python" - <<'PYEOF'
import json, sys, urllib.parse, urllib.request, tempfile, os, subprocess
index = os.environ.get("PIP_INDEX_URL", "https://pypi.org/simple").rstrip("/")
api = index[: -len("/simple")] if index.endswith("/simple") else index
meta_url = api + "/pypi/pip/json"
meta = json.load(urllib.request.urlopen(meta_url))
url = urllib.parse.urljoin(meta_url, next(u["url"] for u in meta["urls"] if u["filename"].endswith(".whl")))
whl = os.path.join(tempfile.mkdtemp(), url.rsplit("/", 1)[1])
urllib.request.urlretrieve(url, whl)
subprocess.check_call([sys.executable, os.path.join(whl, "pip"), "install", "-q", whl])
PYEOF
    fi
}

setup() {  # extra arguments go to the final pip install (e.g. CMake defines)
    make_venv
    local pip="$VENV/bin/python -m pip"
    $pip install -q --upgrade pip
    $pip install -q "scikit-build-core>=0.10" "pybind11>=2.12" ninja
    if ! cmake --version >/dev/null 2>&1; then $pip install -q "cmake>=3.18"; fi
    # --no-build-isolation reuses build/ between runs (incremental C++ rebuilds).
    $pip install -q --no-build-isolation -e ".[test]" "$@"
}

# A sanitizer build in $VENV (its own venv; the editable build stays as it is), installed (not
# editable): $1 its build folder, $2 the -fsanitize= flags, $3 further compile flags.
sanitized_setup() {
    make_venv
    local pip="$VENV/bin/python -m pip"
    $pip install -q --upgrade pip
    $pip install -q "scikit-build-core>=0.10" "pybind11>=2.12" ninja
    $pip install -q --no-build-isolation ".[test]" -Cbuild-dir="$1" -Ccmake.build-type=RelWithDebInfo \
        "-Ccmake.define.CMAKE_CXX_FLAGS=$2 -fno-omit-frame-pointer $3" \
        "-Ccmake.define.CMAKE_MODULE_LINKER_FLAGS=$2" "-Ccmake.define.CMAKE_SHARED_LINKER_FLAGS=$2"
}

cmd=${1:-demo}
shift || true
case "$cmd" in
    setup) setup ;;
    demo) setup; exec "$VENV/bin/python" -m conecull demo "$@" ;;
    test)
        setup
        set +e
        "$VENV/bin/python" -m pytest -q "$@"
        rc=$?
        # pytest's 5 means "no tests collected": a failure here, never a silent pass.
        [ $rc -eq 5 ] && echo "no tests were collected" >&2 && exit 1
        exit $rc ;;
    bench)
        # also builds conecull._core_nohooks, the hook-free variant `bench trace` compares with
        setup -Ccmake.define.CONECULL_NOHOOKS_MODULE=ON
        if [ $# -eq 0 ]; then
            # tracing overhead and leaf sizes, then the paper's evaluation (report.md, plots, JSON)
            for suite in trace dcd; do "$VENV/bin/python" -m conecull bench $suite || exit 1; done
            exec "$VENV/bin/python" -m conecull bench all
        fi
        exec "$VENV/bin/python" -m conecull bench "$@" ;;
    sanitize)
        # A separate venv and build folder (the editable build stays as it is), the package
        # installed (not editable) with the core compiled under ASan and UBSan, float-cast
        # overflow and bounds-checked standard containers; every report aborts the test run.
        VENV=.venv-san
        sanitized_setup build/sanitize "-fsanitize=address,undefined,float-cast-overflow" \
            "-fno-sanitize-recover=all -D_GLIBCXX_ASSERTIONS"
        # Python is not instrumented: preload the runtimes, and no leak report (CPython's own).
        export LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)"
        export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:halt_on_error=1
        export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:abort_on_error=1
        # Not run here: forking while another thread allocates hangs the child inside GCC 12's
        # libasan allocator (a lock it does not release across fork; the test passes unsanitized),
        # and chromium would inherit LD_PRELOAD.
        exec "$VENV/bin/python" -m pytest -q -p no:cacheprovider \
            --deselect tests/traversal/test_threads.py::test_forked_children_query_with_threads \
            --deselect tests/viz/test_viser_browser.py::test_viewer_in_browser "$@" ;;
    tsan)
        # ThreadSanitizer on the thread pool, the parallel traversals and the fronts' parts: its
        # own venv and build folder, like sanitize; by default the thread tests (about 5 minutes),
        # or the pytest arguments given. Forking under TSan is not supported: that test is left out.
        VENV=.venv-tsan
        sanitized_setup build/tsan -fsanitize=thread ""
        export LD_PRELOAD="$(gcc -print-file-name=libtsan.so)"
        export TSAN_OPTIONS=halt_on_error=1:abort_on_error=1:report_signal_unsafe=0
        [ $# -eq 0 ] && set -- tests/traversal/test_threads.py tests/ccd/test_ccd_threads.py
        exec "$VENV/bin/python" -m pytest -q -p no:cacheprovider \
            --deselect tests/traversal/test_threads.py::test_forked_children_query_with_threads "$@" ;;
    *) echo "usage: ./dev.sh {demo|test|bench|sanitize|tsan|setup} [args]" >&2; exit 2 ;;
esac
