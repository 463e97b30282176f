#!/bin/sh
# test_readme_hosts.sh SRC - the README's map across hosts ("Sweeps, and a
# map across hosts"), run on a copy of the source tree so that its build
# directory and its outputs do not stay behind. Its build line and its
# mpirun line run as written (as root, OpenMPI's OMPI_ALLOW_RUN_AS_ROOT*
# variables let mpirun run without changing the line). Its host file names
# the reader's two machines; here the one host with the same four slots is
# written in its place. The map must come out whole (48,441 points, one
# progress bar over the four ranks) and byte-identical to the same map on
# two threads of one process, as the README says. The commands are read from
# README.md and must equal the list below: when the README changes, this
# test changes with it. Run through netns.sh (MPI then talks over a private
# lo only). Takes ~4 min on 2 cores: the build, then the map twice.
src=$1
. "$(dirname "$0")/readme.sh" # readme_block, readme_expect, readme_tree
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v mpirun >/dev/null || fail "mpirun not found (tools/setup.sh installs openmpi-bin)"

readme_block "$src/README.md" \
    '### Sweeps, and a map across hosts (issue 13; figures and commands in `docs/performance.md`)' \
    >"$tmp/block"
cat >"$tmp/want" <<'EOF'
cmake -S . -B build-mpi -DWG_MPI=ON && cmake --build build-mpi -j2
printf 'hostA slots=2\nhostB slots=2\n' > hosts
mpirun --hostfile hosts -np 4 build-mpi/clients/wgsweep --threads 1 --map xi_p=0.05:0.15:201 --step 0.01 --settle 24 --out map
EOF
readme_expect "$tmp/block" "$tmp/want" "host-file commands"
line() { sed -n "${1}p" "$tmp/block"; }

# A copy of the tree as a user has it (no build directories, no .git).
readme_tree "$src" "$tmp/src" ./web/node_modules || fail "could not copy the source tree"
cd "$tmp/src" || exit 1
unset WG_SCENE_PATH # as a user runs it: the scenes come with the build

start=$(date +%s)
sh -c "$(line 1)" >"$tmp/build.log" 2>&1 || { tail -20 "$tmp/build.log"; fail "the build line"; }
[ -x build-mpi/clients/wgsweep ] || fail "no build-mpi/clients/wgsweep after the build line"
echo "build: $(($(date +%s) - start)) s"

# The host file: this host, with the README's four slots.
printf 'localhost slots=4\n' > hosts

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
start=$(date +%s)
sh -c "$(line 3)" >"$tmp/mpi.out" 2>"$tmp/mpi.err"
rc=$?
echo "mpirun: $(($(date +%s) - start)) s, exit $rc"
status=0
check() { if eval "$2"; then echo "$1 ok"; else echo "FAIL: $1"; status=1; fi; }
check "mpirun exits 0" '[ $rc -eq 0 ]'
check "map-map.csv holds 201 x 241 points" '[ $(($(wc -l < map-map.csv) - 1)) -eq 48441 ]'
check "one progress bar over the four ranks, to the end" \
    '[ $(grep -o "100% 48441/48441 points" "$tmp/mpi.err" | wc -l) -eq 1 ] &&
     ! grep -o "[0-9]*/[0-9]* points" "$tmp/mpi.err" | grep -qv "/48441 points"'
check "rank 0 names what it wrote" 'grep -q "201 rows x 241 points in .* s; wrote map-map.csv, map-map.png, map-map-motion.png" "$tmp/mpi.err"'
[ $status -eq 0 ] || { tail -5 "$tmp/mpi.err"; }

start=$(date +%s)
build-mpi/clients/wgsweep --threads 2 --quiet --map xi_p=0.05:0.15:201 --step 0.01 \
    --settle 24 --out threads >/dev/null 2>"$tmp/thr.err"
rc=$?
echo "2 threads, one process: $(($(date +%s) - start)) s, exit $rc"
check "4 ranks and 2 threads write the same bytes" '[ $rc -eq 0 ] && cmp -s map-map.csv threads-map.csv'
exit $status
