#!/bin/sh
# Installs the Debian packages listed in cmake/debian-packages.txt that are
# missing, with apt-get, as root. Does nothing when all are present.
set -eu
here=$(dirname "$0")
list=$(sed -e 's/#.*//' "$here/debian-packages.txt" | tr -s ' \n' ' ')
missing=""
for pkg in $list; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $pkg"
    fi
done
[ -z "$missing" ] && exit 0
echo "softbond: installing Debian packages:$missing"
if [ "$(id -u)" -ne 0 ]; then
    echo "softbond: run as root (or install these packages by hand):$missing" >&2
    exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends $missing
