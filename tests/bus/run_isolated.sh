#!/bin/sh
# Runs a command on its own bus: a fresh network namespace with lo up and the multicast route
# on lo, so LCM traffic never leaves the process tree and tests may run in parallel.
# As root `unshare -n` suffices; otherwise a user namespace maps us to root inside it.
set -e
if [ "$(id -u)" -eq 0 ]; then flags="-n"; else flags="-rn"; fi
exec unshare $flags sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"' sh "$@"
