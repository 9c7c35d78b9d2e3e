#!/usr/bin/env bash
# Component sources use RTT's OS abstractions only, so the same code builds
# for Xenomai's POSIX skin and no hook blocks behind RTT's back: this check
# fails on standard or POSIX threads, sleeps and direct clock reads in the
# RTT layer (rtt/components/*, rtt/deploy). Use instead: an RTT activity
# (threads), RTT::os::TimeService / rtos_get_time_ns (time), a
# FileDescriptorActivity timeout or a periodic activity (waiting),
# rtos_nanosleep (non-hook waits of deployment helpers).
#
#   scripts/realtime/rt_check_sources.sh            check the repository's RTT layer
#   scripts/realtime/rt_check_sources.sh DIR...     check the C++ files under DIR...
# Prints each offending line (comments stripped) and a count; exit 1 if any.
# ctest: rt_component_sources (the repository) and rt_component_sources_detects
# (tests/rt_check/fixture, one planted call of each kind: the check must fail).
set -u
here=$(cd "$(dirname "$0")/../.." && pwd)
if [ $# -eq 0 ]; then
  set -- "$here"/rtt/components/* "$here"/rtt/deploy
fi
# One alternative per forbidden call (extended regex; `_` counts as a word
# character, so rtos_nanosleep is not nanosleep).
forbidden=(
  'std::thread|std::jthread|std::async|#include[[:space:]]*<(thread|future)>|pthread_create'
  'std::this_thread'
  '(^|[^_[:alnum:]])(sleep_for|sleep_until|usleep|nanosleep|clock_nanosleep)[[:space:]]*\('
  '(^|[^_[:alnum:]])(::)?sleep[[:space:]]*\([[:space:]]*[0-9]'
  '_clock::now|(^|[^_[:alnum:]])(clock_gettime|gettimeofday|timespec_get)[[:space:]]*\('
  '(^|[^_[:alnum:].>])time[[:space:]]*\([[:space:]]*(NULL|nullptr|0)?[[:space:]]*\)'
)
pattern=$(IFS='|'; echo "${forbidden[*]}")
count=0
nfiles=0
while IFS= read -r -d '' f; do
  nfiles=$((nfiles + 1))
  # strip // comments (and whole-line /* */ comment lines) before matching
  hits=$(sed -e 's://.*$::' -e 's:/\*.*\*/::g' "$f" | grep -nE "$pattern" || true)
  if [ -n "$hits" ]; then
    while IFS= read -r h; do
      echo "${f#"$here"/}:${h}"
      count=$((count + 1))
    done <<< "$hits"
  fi
done < <(find "$@" -type f \( -name '*.cpp' -o -name '*.cc' -o -name '*.hpp' -o -name '*.h' \) -print0 | sort -z)
if [ "$nfiles" -eq 0 ]; then
  echo "rt_check_sources: no C++ file under: $*" >&2
  exit 2
fi
if [ "$count" -gt 0 ]; then
  echo "rt_check_sources: ${count} forbidden call(s) in ${nfiles} file(s): threads, sleeps and clock reads go through RTT (activities, TimeService, rtos_*)"
  exit 1
fi
echo "rt_check_sources: ${nfiles} file(s) clean (no std::thread, sleeps or direct clock reads)"
