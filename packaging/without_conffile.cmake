# SPDX-License-Identifier: LGPL-2.1-or-later
# Run by CPack on the staged files before it makes the package
# (CPACK_PRE_BUILD_SCRIPTS). The configuration file goes in the package as
# /usr/share/causticd/causticd.conf only, which postinst hands to ucf: in
# /etc it would be a dpkg conffile, whose question stops a non-interactive
# upgrade over an operator's edit. `cmake --install` alone still puts it in
# /etc (systemd/CMakeLists.txt).
# The folder stays the package's: dpkg neither warns that it cannot remove it
# (an operator's files are there) nor leaves it behind a purge.
file(REMOVE "${CPACK_TEMPORARY_DIRECTORY}/etc/causticd/causticd.conf")
