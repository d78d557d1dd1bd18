# Shared helpers of the CLI pipeline tests (tests/cli/*.sh). Each check counts into
# $passes / $failures; scripts end with `finish`.
#
# The preamble of every script is the one line
#     source "$(dirname "$0")/lib/harness.bash"
# which, run as `X.sh TOOL_DIR SOURCE_DIR WORK_DIR` (tests/CMakeLists.txt), sets $tools,
# $src and $work, empties $work and turns on `set -u`. A script that sets $work itself
# before sourcing (the old preamble) keeps what it made there.
if [ -z "${work+x}" ]; then
    set -u
    tools=$1
    src=$2
    work=$3
    rm -rf "$work"
    mkdir -p "$work"
fi
passes=0
failures=0

# expect CODE DESCRIPTION -- command...: the command exits with CODE. Its stdout and
# stderr are kept in $work/out and $work/err for later checks.
expect() {
    local want=$1 what=$2
    shift 3
    "$@" >"$work/out" 2>"$work/err"
    local got=$?
    if [ "$got" -eq "$want" ]; then
        passes=$((passes + 1))
    else
        failures=$((failures + 1))
        echo "FAILED: $what: exit $got, expected $want"
        sed 's/^/  stdout: /' "$work/out" | head -5
        sed 's/^/  stderr: /' "$work/err" | head -5
    fi
}

# contains FILE TEXT DESCRIPTION: FILE contains TEXT literally.
contains() {
    if grep -qF -- "$2" "$1"; then
        passes=$((passes + 1))
    else
        failures=$((failures + 1))
        echo "FAILED: $3: '$2' not in output"
        head -5 "$1" | sed 's/^/  /'
    fi
}

# ok DESCRIPTION -- test-command...: the command succeeds.
ok() {
    local what=$1
    shift 2
    if "$@"; then
        passes=$((passes + 1))
    else
        failures=$((failures + 1))
        echo "FAILED: $what"
    fi
}

# Prints the closing line CTest and CI read, and sets the exit status.
finish() {
    echo "$passes passed, $failures failed"
    [ "$failures" -eq 0 ]
}
