#!/usr/bin/env bash
# The function-length limit, enforced: clang-tidy's readability-function-size
# (scripts/lint/function_size.yaml: no function body over 100 lines) over
# every non-test C++ source of a build tree's compile_commands.json
# (core/, rtt/, devices/, tools/; tests and generated code excluded), and the
# project headers they include. Exits 1 and lists the functions when one is
# over the limit.
#
# usage: function_size.sh [BUILD_DIR]   (default: build; jobs: TACTILE_JOBS or nproc)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
db="$build/compile_commands.json"
[ -f "$db" ] || { echo "function_size: no $db (configure with CMAKE_EXPORT_COMPILE_COMMANDS=ON)" >&2; exit 2; }
command -v clang-tidy > /dev/null || { echo "function_size: clang-tidy not found (Debian: clang-tidy)" >&2; exit 2; }
files="$(/usr/bin/python3 - "$db" "$root" <<'PY'
import json, re, sys
db, root = sys.argv[1], sys.argv[2]
keep = re.compile(re.escape(root) + r"/(core|rtt|devices|tools)/(?!(.*/)?tests?/).*\.cpp$")
print("\n".join(sorted({e["file"] for e in json.load(open(db)) if keep.match(e["file"])})))
PY
)"
n=$(printf '%s\n' "$files" | grep -c . || true)
[ "$n" -gt 0 ] || { echo "function_size: no source in $db" >&2; exit 2; }
echo "function_size: clang-tidy readability-function-size (100 lines) over $n sources"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
printf '%s\n' "$files" | xargs -P "${TACTILE_JOBS:-$(nproc)}" -I{} \
  clang-tidy -p "$build" --config-file="$root/scripts/lint/function_size.yaml" --quiet {} > "$log" 2>&1 || true
over="$(grep -E "warning|error: function" "$log" | grep "readability-function-size" | sed "s|$root/||" | sort -u || true)"
if [ -n "$over" ]; then
  echo "$over"
  echo "function_size: $(printf '%s\n' "$over" | grep -c .) functions over 100 lines"
  exit 1
fi
if grep -qE "^Error|error:" "$log"; then
  grep -E "error:" "$log" | head -n 20 >&2
  echo "function_size: clang-tidy failed on a source (above)" >&2
  exit 2
fi
echo "function_size: every function within 100 lines"
