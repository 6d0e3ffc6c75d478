#!/usr/bin/env bash
# Installs bayesbem from the repository root (extra arguments go to
# R CMD INSTALL, e.g. -l <library> or --preclean). The compilers' output
# goes to a log, not the screen: compiling the Stan programs floods it with
# warnings from Eigen's, Boost's and StanHeaders' headers, none of them
# about bayesbem's code. Prints one line: the time,
# the warnings counted by source (bayesbem's own are shown in full) and the
# log's path; on failure, the log's end.
set -euo pipefail
cd "$(dirname "$0")/.."
log="${BAYESBEM_INSTALL_LOG:-${TMPDIR:-/tmp}/bayesbem-install.log}"
started=$(date +%s)
# R's C++14 flags without debugging symbols (-g0 for -g): the same code,
# compiled faster and a library a thirtieth the size
# (bench/results/install-times.md); a user's own R_MAKEVARS_USER is kept.
if [ -z "${R_MAKEVARS_USER:-}" ]; then
  makevars="$(mktemp)"
  trap 'rm -f "$makevars"' EXIT
  echo "CXX14FLAGS = $(R CMD config CXX14FLAGS | sed -E 's/(^| )-g( |$)/\1-g0\2/')" > "$makevars"
  export R_MAKEVARS_USER="$makevars"
fi
if ! MAKEFLAGS="${MAKEFLAGS:--j$(nproc)}" R CMD INSTALL "$@" . > "$log" 2>&1; then
  tail -40 "$log"
  echo "install: R CMD INSTALL failed; the whole output is in $log"
  exit 1
fi
all=$(grep -c "warning:" "$log" || true)
# bayesbem's own sources: src/ and inst/include/ (paths relative to src/)
own=$(grep "warning:" "$log" | grep -E "^([a-zA-Z_]+\.(cc|cpp|h)|\.\./inst/include/)" || true)
if [ -n "$own" ]; then echo "$own"; fi
echo "install: bayesbem installed in $(( $(date +%s) - started )) s;" \
  "$all compiler warnings, $(printf '%s' "$own" | grep -c . || true) of them in bayesbem's code; log: $log"
