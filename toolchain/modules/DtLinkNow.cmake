# Every program and shared library resolves its dynamic symbols when it is loaded (-z now), not at
# the first call (lazy binding): the haptic thread then never enters the dynamic linker after its
# warm-up, whose page faults and locks the real-time path must not take (docs/memory.md). Debian
# builds its packages the same way (dpkg-buildflags' hardening "bindnow"); read-only relocations
# (-z relro) come with it.
add_link_options(LINKER:-z,now LINKER:-z,relro)
