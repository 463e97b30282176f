# readme.sh - sourced by the tests that run the README's commands
# (test_readme.sh, test_readme_hosts.sh, test_readme_bench.sh): a fenced
# block's commands, the check that they are the list the test runs, and a
# copy of the tree to run them in.

# readme_block README HEADING [K]: the K-th fenced block (default 1) of the
# section that starts at the line HEADING (up to the next "## " heading),
# continuation lines joined, comments and blank lines dropped.
readme_block() {
    awk -v h="$2" -v k="${3:-1}" '$0 == h { on = 1; next } on && /^## / { exit }
        on && /^```/ { if (++f == 2 * k) exit; next } on && f == 2 * k - 1 { print }' "$1" |
        sed -e ':a' -e '/\\$/N; s/[ ]*\\\n[ ]*/ /; ta' -e 's/[ ]\+#.*$//' -e '/^$/d'
}

# readme_expect GOT WANT WHAT: the README's commands GOT must be the list
# WANT the test runs; else say so with the difference and exit 1.
readme_expect() {
    cmp -s "$1" "$2" && return 0
    echo "FAIL: the README's $3 are not what this test checks; update both:"
    diff "$2" "$1"
    exit 1
}

# readme_tree SRC DEST [EXCLUDE...]: a copy of the tree SRC in DEST (made
# here) as a user has it: no .git, no build directories, nor the EXCLUDEd
# paths (./web/node_modules, say); mtimes kept. 0, or 1.
readme_tree() {
    local src=$1 dest=$2 ex=
    shift 2
    for e in "$@"; do ex="$ex --exclude=$e"; done
    mkdir -p "$dest" &&
        (cd "$src" && tar --exclude=./.git --exclude=./build --exclude='./build-*' $ex -cf - .) |
        (cd "$dest" && tar -xf -)
}
