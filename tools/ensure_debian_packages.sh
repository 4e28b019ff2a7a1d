#!/bin/sh
# Install the Debian packages named on the command line that are missing.
# A name may carry an architecture (libgpiod-dev:armhf): that architecture is added to dpkg first (multiarch).
# As root they are installed with apt-get; otherwise one message lists them and we fail.
set -eu
missing=""
for pkg in "$@"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  case "$status" in
    *"ok installed"*) ;;
    *) missing="$missing $pkg" ;;
  esac
done
[ -z "$missing" ] && exit 0
foreign=""
for pkg in $missing; do
  case "$pkg" in
    *:*) arch=${pkg#*:}
         case " $foreign " in *" $arch "*) continue ;; esac
         if [ "$arch" != "$(dpkg --print-architecture)" ] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
           foreign="$foreign $arch"
         fi ;;
  esac
done
if [ "$(id -u)" -ne 0 ]; then
  echo "error: missing Debian packages:$missing" >&2
  for arch in $foreign; do echo "       first: sudo dpkg --add-architecture $arch" >&2; done
  echo "       install them with: sudo apt-get update && sudo apt-get install$missing" >&2
  exit 1
fi
for arch in $foreign; do
  echo "Adding the Debian architecture $arch (for$missing)"
  dpkg --add-architecture "$arch"
done
echo "Installing missing Debian packages:$missing"
export DEBIAN_FRONTEND=noninteractive
# a mirror in sync can fail one index (e.g. security for a foreign architecture): try the install all the same
apt-get update -qq || echo "warning: apt-get update reported errors (above); installing from the indexes it has"
# shellcheck disable=SC2086
apt-get install -y -qq --no-install-recommends $missing
