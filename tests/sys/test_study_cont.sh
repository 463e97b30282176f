#!/bin/sh
# test_study_cont.sh SRC BUILD - docs/study/cont/make.sh, run on a copy of
# that directory with this build, writes every kept bifurcation CSV,
# steps.md and table3-exact.md as they are committed: byte for byte here,
# and on a CPU whose libm gives other last bits (glibc chooses its sin/cos
# by CPU features) the same text with every number within 1e-9
# (same_numbers.py): the continuation study in the docs is what this code
# computes. (The figures are checked to exist only: their bytes depend on
# cairo's and the fonts' versions.)
src=$1 build=$2
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/docs/study/cont"
cp -r "$src/scenes" "$tmp/"
cp "$src/docs/study/table3.csv" "$tmp/docs/study/"
cp "$src/docs/study/cont/make.sh" "$src/docs/study/cont/compare_cont.py" "$tmp/docs/study/cont/"
cd "$tmp/docs/study/cont" || exit 1
start=$(date +%s)
sh make.sh "$build" || { echo "FAIL: make.sh exit $?"; exit 1; }
echo "make.sh: $(($(date +%s) - start)) s"
fail=0
n=0 same=0
for f in "$src"/docs/study/cont/*.csv "$src"/docs/study/cont/*.md; do
    b=$(basename "$f")
    [ "$b" = README.md ] && continue
    n=$((n + 1))
    if cmp -s "$f" "$b"; then
        echo "same $b"
        same=$((same + 1))
    elif [ -f "$b" ] && python3 "$here/same_numbers.py" "$f" "$b"; then
        echo "within 1e-9: $b" # glibc's sin/cos differ by CPU in the last bits
    else
        echo "FAIL: $b differs or is missing"
        fail=1
    fi
done
for f in "$src"/docs/study/cont/*.png; do
    b=$(basename "$f")
    [ -s "$b" ] || { echo "FAIL: $b not written"; fail=1; }
done
extra=$(for f in ./*.csv ./*.md ./*.png; do [ -e "$src/docs/study/cont/$f" ] || echo "$f"; done)
[ -z "$extra" ] || { echo "FAIL: written but not committed: $extra"; fail=1; }
[ $n -ge 12 ] || { echo "FAIL: only $n files compared"; fail=1; }
[ $fail -eq 0 ] && echo "ok: $n files, $same of them byte-identical, the rest within 1e-9"
exit $fail
