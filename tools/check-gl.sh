#!/bin/sh
# Mesa's EGL and software rasteriser are facet's only system requirement (or, without EGL,
# Mesa's OSMesa, which carries its own llvmpipe); say in one line what to install when
# neither is there.
missing=""
ldconfig -p 2>/dev/null | grep -q 'libEGL\.so\.1 ' || missing="$missing libegl1"
found=""
for f in /usr/lib/*/dri/swrast_dri.so /usr/lib/dri/swrast_dri.so /usr/lib64/dri/swrast_dri.so; do
  [ -e "$f" ] && found=1
done
[ -n "$found" ] || missing="$missing libgl1-mesa-dri"
if [ -n "$missing" ]; then
  if ldconfig -p 2>/dev/null | grep -q 'libOSMesa\.so\.[68] '; then
    echo "facet: no EGL here (missing:$missing); rendering through OSMesa" >&2
    exit 0
  fi
  echo "facet needs Mesa's EGL and llvmpipe: sudo apt-get install$missing" \
       "(or, without EGL, libosmesa6)" >&2
  exit 1
fi
