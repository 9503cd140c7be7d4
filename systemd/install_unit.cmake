# Runs at install time (`cmake --install`, and cpack, which installs with the prefix /usr): writes
# volcompd.service (or the LinuxCNC drop-in, volcompd-linuxcnc.conf) with the absolute paths of
# that installation and installs it into VOLCOMP_UNIT_DIR. The paths are taken from the
# install-time prefix, not the configure-time one, so that a package built from a tree configured
# for /usr/local still starts /usr/sbin/volcompd.
#
# Set by the install(CODE) in systemd/CMakeLists.txt: VOLCOMP_UNIT_TEMPLATE, VOLCOMP_UNIT_OUTPUT,
# VOLCOMP_UNIT_DIR, VOLCOMP_SBINDIR, VOLCOMP_SYSCONFDIR, VOLCOMP_DOCDIR, VOLCOMP_CONFIG_OVERRIDE.

function(volcomp_full_path out dir)
  if(IS_ABSOLUTE "${dir}")
    set(${out} "${dir}" PARENT_SCOPE)
  else()
    set(${out} "${CMAKE_INSTALL_PREFIX}/${dir}" PARENT_SCOPE)
  endif()
endfunction()

# GNUInstallDirs' rule for the configuration directory: /etc for the prefixes / and /usr,
# /etc/opt/NAME for /opt/NAME, <prefix>/etc otherwise.
if(IS_ABSOLUTE "${VOLCOMP_SYSCONFDIR}")
  set(sysconfdir "${VOLCOMP_SYSCONFDIR}")
elseif(CMAKE_INSTALL_PREFIX MATCHES "^/(usr/?)?$")
  set(sysconfdir "/${VOLCOMP_SYSCONFDIR}")
elseif(CMAKE_INSTALL_PREFIX MATCHES "^/opt/")
  set(sysconfdir "/etc${CMAKE_INSTALL_PREFIX}")
else()
  set(sysconfdir "${CMAKE_INSTALL_PREFIX}/${VOLCOMP_SYSCONFDIR}")
endif()

volcomp_full_path(sbindir "${VOLCOMP_SBINDIR}")
volcomp_full_path(VOLCOMP_DOC_DIR "${VOLCOMP_DOCDIR}")
volcomp_full_path(unitdir "${VOLCOMP_UNIT_DIR}")
set(VOLCOMPD_PATH "${sbindir}/volcompd")
set(VOLCOMPD_LINUXCNC_PATH "${sbindir}/volcompd-linuxcnc")
if(VOLCOMP_CONFIG_OVERRIDE)
  set(VOLCOMPD_CONFIG "${VOLCOMP_CONFIG_OVERRIDE}")
else()
  set(VOLCOMPD_CONFIG "${sysconfdir}/volcomp/volcompd.json")
endif()

configure_file("${VOLCOMP_UNIT_TEMPLATE}" "${VOLCOMP_UNIT_OUTPUT}" @ONLY)
# file(INSTALL) honours DESTDIR and records the file in the install manifest.
file(INSTALL DESTINATION "${unitdir}" TYPE FILE FILES "${VOLCOMP_UNIT_OUTPUT}")
