#!/bin/sh
# The maintainer scripts under `dpkg --root` ($DPKG_ROOT): the user is made in that root, purge
# removes that root's /var/lib/depthtouch and not this system's, and neither systemd nor udev of
# the running system is called (debhelper's generated scripts behave so). The tools are stubs on
# PATH that log their arguments. Usage: dpkg_root_check.sh DIR-WITH-postinst-prerm-postrm WORK
set -u
scripts="$1"
work="$2"
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work/bin" "$work/root/var/lib/depthtouch" || exit 1
touch "$work/root/var/lib/depthtouch/recording.mkv"
for tool in systemd-sysusers deb-systemd-helper deb-systemd-invoke systemctl udevadm; do
    printf '#!/bin/sh\necho "%s $*" >> "%s/calls"\n' "$tool" "$work" > "$work/bin/$tool"
    chmod +x "$work/bin/$tool"
done
: > "$work/calls"
run() { PATH="$work/bin:$PATH" DPKG_ROOT="$work/root" sh "$scripts/$1" "$2" || fail "$1 $2: exit $?"; }
run postinst configure
run prerm remove
run postrm remove
run postrm purge
[ -e "$work/root/var/lib/depthtouch" ] && fail "purge left \$DPKG_ROOT/var/lib/depthtouch"
grep -qx "systemd-sysusers --root=$work/root depthtouch.conf" "$work/calls" ||
    fail "the user is not made in \$DPKG_ROOT: $(cat "$work/calls")"
grep -E "^(systemctl|udevadm|deb-systemd-invoke) " "$work/calls" &&
    fail "the running system's systemd or udev was called under dpkg --root"
echo "dpkg --root: user made in the root, its state folder purged, the running system untouched"
