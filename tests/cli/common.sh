# common.sh -- helpers sourced by the end-to-end tests tests/cli/test_*.sh.
#   usage: bash tests/cli/test_X.sh PATH/TO/gigatet
# Each test script runs the real binary, counts failures and exits 0 (all passed), 1 (a
# failure) or 77 (skipped: ctest's SKIP_RETURN_CODE; only when a required tool is really
# missing, and then it says so loudly on stdout and stderr).
set -u
G=${1:?usage: $0 PATH/TO/gigatet}
case "$G" in /*) ;; *) G="$PWD/$G" ;; esac
T=$(mktemp -d "${TMPDIR:-/tmp}/gtet-cli-XXXXXX")
trap 'chmod -R u+w "$T" 2>/dev/null; rm -rf "$T"' EXIT
W="$T/work"; mkdir "$W"   # the tests work in $W; $T/out, $T/err hold the last command's output
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
fails=0

fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
pass() { echo "ok   $*"; }

# expect CODE STDERR_SUBSTRING -- CMD ARGS...: run CMD, require the exit code and (when not
# empty) the substring in its stderr.  stdout/stderr are kept in $T/out and $T/err.
expect() {
    local code=$1 pat=$2
    shift 3
    "$@" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ "$rc" -ne "$code" ]; then
        fail "'$*' exited $rc, expected $code; stderr: $(head -c 400 "$T/err")"
    elif [ -n "$pat" ] && ! grep -qF -- "$pat" "$T/err"; then
        fail "'$*': stderr lacks '$pat': $(head -c 400 "$T/err")"
    else
        pass "$* -> $code"
    fi
}

# A python3 interpreter that can import module $1 (Debian's modules live under /usr/bin/python3,
# which a pyenv python3 on PATH does not see).  Prints nothing and fails when there is none.
find_python() {
    local py
    for py in /usr/bin/python3 python3; do
        if command -v "$py" >/dev/null 2>&1 && "$py" -c "import $1" >/dev/null 2>&1; then
            echo "$py"
            return 0
        fi
    done
    return 1
}

skip_loudly() {
    echo "SKIPPED (LOUDLY): $*"
    echo "SKIPPED (LOUDLY): $*" >&2
    exit 77
}

# Entries of directory $1 (none expected after a failed run).
listing() { ls -A "$1" | tr '\n' ' '; }

finish() {
    if [ "$fails" -ne 0 ]; then
        echo "$fails failure(s)"
        exit 1
    fi
    echo "all passed"
    exit 0
}
