#!/usr/bin/env bash
# Installs Debian's Slurm (slurmctld, slurmd, slurm-client) and munge for a one-node cluster on loopback.
# Does nothing when they are installed. Services are not started: tools/slurm/start.sh runs the daemons itself
# (there may be no systemd, e.g. in CI containers). Needs root or sudo.
set -euo pipefail
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "slurm: installed ($(dpkg-query -W -f='${Version}' slurmctld))"
  exit 0
fi
sudo=""
[[ $(id -u) -eq 0 ]] || sudo=sudo
# Without a policy-rc.d the packages' scripts would try to start the services; 101 = "action forbidden".
policy=/usr/sbin/policy-rc.d
made_policy=0
if [[ ! -e $policy ]]; then
  printf '#!/bin/sh\nexit 101\n' | $sudo tee "$policy" >/dev/null
  $sudo chmod 755 "$policy"
  made_policy=1
fi
remove_policy() { ((made_policy)) && $sudo rm -f "$policy"; return 0; }
trap remove_policy EXIT
echo "slurm: installing ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
echo "slurm: installed ($(dpkg-query -W -f='${Version}' slurmctld))"
