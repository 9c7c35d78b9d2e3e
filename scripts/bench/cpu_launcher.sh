#!/bin/sh
# Compiler and linker launcher for build_profile.py: runs the command under
# /usr/bin/time and appends "user_s sys_s wall_s cwd output" to
# $TACTILE_CPU_LOG (one line per compile or link; without TACTILE_CPU_LOG it
# only runs the command). Used as
#   cmake -DCMAKE_CXX_COMPILER_LAUNCHER=<this> -DCMAKE_CXX_LINKER_LAUNCHER=<this>
if [ -z "${TACTILE_CPU_LOG:-}" ]; then exec "$@"; fi
out=""
prev=""
for a in "$@"; do
  if [ "$prev" = "-o" ]; then out="$a"; fi
  prev="$a"
done
exec /usr/bin/time -a -o "$TACTILE_CPU_LOG" -f "%U %S %e $PWD $out" "$@"
