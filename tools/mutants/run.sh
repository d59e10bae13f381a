#!/usr/bin/env bash
# Mutation testing of paraflex's numerical kernels with cargo-mutants (docs/mutation-testing.md).
#
#   tools/mutants/run.sh FILE...                 every mutant of each file
#   MUTANTS_RE='regex' tools/mutants/run.sh F    rerun only the mutants whose names match
#   MUTANTS_ITERATE=1 tools/mutants/run.sh F     rerun every mutant of F not caught so far
#   MUTANTS_SHARD=k/n tools/mutants/run.sh F     a sample: every n-th mutant of F from the k-th
#                                                (k = 0 … n−1; cargo-mutants' round-robin shard)
#
# Each file is mutated in its own cargo-mutants run against the tests tools/mutants/modules.tsv
# assigns it, and its outcomes land in mutants.out/<file, / as ->/mutants.out/ (a rerun's in
# mutants.out/<file>-rerun-<time>/mutants.out/) with the command (command.txt) and the commit
# (commit.txt) that produced them; tools/mutants/record.py then copies the outcomes into the
# repository's ledger (tools/mutants/ledger/, committed), from which tools/mutants/report.py
# writes docs/mutation-testing.md.
#
# A sample (MUTANTS_SHARD) is a file's first run when the ledger has none yet, and a rerun
# otherwise (another shard adds its mutants to the earlier ones); it records the file's whole
# mutant count (file-mutants.txt) so that the report says what fraction was sampled.
#
# Affordability on a small shared machine: one job under `nice -n 19`, so it only takes idle CPU;
# a target directory of its own (target/mutants, its dependencies hard-linked from target/debug
# when it is first made; both under CARGO_TARGET_DIR when that is set), so that it never waits
# for the developer's builds on cargo's lock; paraflex itself at opt-level 0 without debug
# information and with incremental compilation, so that a mutant costs the recompilation of the
# functions it touched, not of the crate.
set -euo pipefail

root=$(git rev-parse --show-toplevel)
cd "$root"
modules=tools/mutants/modules.tsv
build=${CARGO_TARGET_DIR:-$root/target}
target=${MUTANTS_TARGET_DIR:-$build/mutants}
out_root=${MUTANTS_OUT:-$root/mutants.out}
[ $# -gt 0 ] || { echo "usage: $0 FILE..." >&2; exit 2; }

if [ ! -d "$target" ] && [ -d "$build/debug" ]; then
    # hard links cost no space; paraflex's own artifacts are left out so that neither tree ever
    # writes into the other's files
    mkdir -p "$target"
    cp -al "$build/debug" "$target/debug"
    find "$target/debug" -depth -name '*paraflex*' -exec rm -rf {} +
    # cargo's lock on the build directory must be a file of its own, or each tree waits for the
    # other's builds
    rm -f "$target/debug/.cargo-lock"
fi

# Pure message formatting is not numerics: Display and Debug implementations are not mutated.
exclude='impl .*(Display|Debug) for'
commit=$(git rev-parse --short HEAD)
[ -z "$(git status --porcelain -- src tests)" ] || commit="$commit (with uncommitted changes)"

for file in "$@"; do
    filter=$(awk -F'\t' -v f="$file" '$1 == f { print $2 }' "$modules")
    [ -n "$filter" ] || { echo "$file: no test filter in $modules" >&2; exit 2; }
    name=${file#src/}
    name=${name%.rs}
    name=${name//\//-}
    if [ -n "${MUTANTS_RE:-}${MUTANTS_ITERATE:-}" ] ||
        { [ -n "${MUTANTS_SHARD:-}" ] && [ -f "tools/mutants/ledger/$name.json" ]; }; then
        # a rerun (after new tests) is kept beside the file's full run, whose outcomes it
        # updates in the report; --iterate reads which mutants were already caught from a copy
        # of the latest run's lists
        previous="$out_root/$name"
        for d in "$out_root/$name"-rerun-*; do
            [ ! -d "$d" ] || previous=$d
        done
        out="$out_root/$name-rerun-$(date -u +%Y%m%dT%H%M%S)"
        if [ -n "${MUTANTS_ITERATE:-}" ]; then
            mkdir -p "$out/mutants.out"
            cp "$previous"/mutants.out/*.txt "$out/mutants.out/"
        fi
    else
        rm -rf "$out_root/$name" "$out_root/$name"-rerun-*
        out="$out_root/$name"
    fi
    mkdir -p "$out"
    # --lib goes to every cargo call (cargo-mutants' build phase, `cargo test --no-run`, would
    # otherwise build every test target); the filter after `--` only to the test run
    cmd=(nice -n 19 cargo mutants --jobs 1 --file "$file" --exclude-re "$exclude"
        --minimum-test-timeout 60 --output "${out#"$root"/}" --cargo-arg=--lib
        --cargo-arg=--config=profile.dev.package.paraflex.opt-level=0
        --cargo-arg=--config=profile.dev.package.paraflex.debug=false)
    [ -z "${MUTANTS_RE:-}" ] || cmd+=(--re "$MUTANTS_RE")
    [ -z "${MUTANTS_ITERATE:-}" ] || cmd+=(--iterate)
    if [ -n "${MUTANTS_SHARD:-}" ]; then
        cmd+=(--shard "$MUTANTS_SHARD" --sharding round-robin)
        cargo mutants --list --file "$file" --exclude-re "$exclude" | wc -l > "$out/file-mutants.txt"
    fi
    cmd+=(-- -- "$filter")
    {
        printf 'CARGO_TARGET_DIR=%q CARGO_INCREMENTAL=1 ' "${target#"$root"/}"
        printf '%q ' "${cmd[@]}" | sed 's/ $//'
    } > "$out/command.txt"
    echo "$commit" > "$out/commit.txt"
    echo "== $file: $(cat "$out/command.txt")"
    # cargo-mutants exits 2 when mutants were missed and 3 when some timed out: both are results
    # for the report; anything else (a failing baseline, bad arguments) stops the run
    rc=0
    CARGO_TARGET_DIR=$target CARGO_INCREMENTAL=1 "${cmd[@]}" || rc=$?
    case $rc in
    0 | 2 | 3) python3 tools/mutants/record.py "$out" ;;
    *) echo "cargo mutants failed on $file (exit $rc)" >&2; exit "$rc" ;;
    esac
done
