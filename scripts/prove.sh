#!/usr/bin/env bash
# Runs the prove scripts (scripts/prove-*.sh, the frame in scripts/prove-common.sh) with one
# build: in one throwaway git worktree of HEAD, every script's recipe in turn, each checked on its
# own and committed there before the next; then one Release build of rodend and the Python
# module; then every script's check. Exit 1 naming the scripts whose recipe or check failed;
# 77 (skipped) outside a git checkout. CTest runs it as `prove` (label prove).
# Usage: bash scripts/prove.sh [NAME ...]   (NAME: catalogues, record, ...; default: all)
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
git rev-parse --verify -q HEAD > /dev/null 2>&1 ||
  { echo "prove: not a git checkout with a commit (it works in a worktree of HEAD): skipped"; exit 77; }
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for f in scripts/prove-*.sh; do
    n=${f#scripts/prove-}
    n=${n%.sh}
    [ "$n" = common ] || names+=("$n")
  done
fi
PROVE_WORK=$(mktemp -d)
PROVE_TREE="$PROVE_WORK/tree"
export PROVE_WORK PROVE_TREE
cleanup() {
  git -C "$repo" worktree remove --force "$PROVE_TREE" > /dev/null 2>&1 || true
  rm -rf "$PROVE_WORK"
}
trap cleanup EXIT
git worktree add --detach "$PROVE_TREE" HEAD > /dev/null
for n in "${names[@]}"; do
  echo "== recipe: prove-$n"
  PROVE_PHASE=recipe bash "$PROVE_TREE/scripts/prove-$n.sh" ||
    { echo "prove: the recipe of prove-$n failed" >&2; exit 1; }
done
echo "== build"
(
  PROVE_PHASE=none
  source "$PROVE_TREE/scripts/prove-common.sh"
  prove_build
)
failed=()
for n in "${names[@]}"; do
  echo "== check: prove-$n"
  PROVE_PHASE=check bash "$PROVE_TREE/scripts/prove-$n.sh" || failed+=("prove-$n")
  git -C "$PROVE_TREE" checkout -q -- .  # what a check regenerated (gen-docs)
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "prove: failed: ${failed[*]}" >&2
  exit 1
fi
echo "prove: ${#names[@]} recipes, one build: ok (${names[*]})"
