# The Debian package (docs/operations.md, "Install on a gateway"): install rules and CPack's DEB
# generator.
# `cpack` in a build tree writes tiltgate_<version>_<arch>.deb; scripts/package makes one from
# a release tree, tests/e2e/package_test.sh from build/.
include_guard(GLOBAL)

# `cmake --install` and cpack install what is built, without first building every target (the
# test programs and benchmarks are not packaged): scripts/package builds only `tiltgate` and
# `tiltgate_package_files`, and build/ has both.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

set(packaging ${PROJECT_SOURCE_DIR}/packaging)
set(generated ${PROJECT_BINARY_DIR}/packaging)

# tiltgate(1) from the program's own --help (and each command's); through the emulator (qemu)
# when cross-compiling, as ctest runs the tests.
add_custom_command(OUTPUT ${generated}/tiltgate.1.gz
                   COMMAND bash ${packaging}/make_manpage.sh ${generated}/tiltgate.1
                           ${PROJECT_VERSION} ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:tiltgate>
                   COMMAND gzip -9nf ${generated}/tiltgate.1
                   DEPENDS tiltgate ${packaging}/make_manpage.sh
                   COMMENT "Writing the man page tiltgate(1)")
configure_file(${packaging}/changelog.in ${generated}/changelog @ONLY)
# A native package (its version has no Debian revision): Debian policy 12.7 names its changelog
# changelog.gz, not changelog.Debian.gz (lintian: wrong-name-for-changelog-of-native-package).
add_custom_command(OUTPUT ${generated}/changelog.gz
                   COMMAND gzip -9nf ${generated}/changelog
                   DEPENDS ${packaging}/changelog.in
                   COMMENT "Compressing the Debian changelog")
add_custom_command(OUTPUT ${generated}/tiltgate.toml
                   COMMAND ${CMAKE_COMMAND} -DINPUT=${PROJECT_SOURCE_DIR}/examples/tiltgate.toml
                           -DOUTPUT=${generated}/tiltgate.toml -P ${packaging}/packaged_config.cmake
                   DEPENDS ${PROJECT_SOURCE_DIR}/examples/tiltgate.toml ${packaging}/packaged_config.cmake
                   COMMENT "Making the packaged configuration")
add_custom_target(tiltgate_package_files ALL DEPENDS ${generated}/tiltgate.1.gz
                  ${generated}/changelog.gz ${generated}/tiltgate.toml)

set(doc share/doc/tiltgate)
install(TARGETS tiltgate RUNTIME DESTINATION bin)
install(FILES ${generated}/tiltgate.toml DESTINATION /etc/tiltgate)
# Debian 12 keeps units in /lib (merged /usr, but lintian still wants them there).
install(FILES ${packaging}/tiltgate.service DESTINATION /lib/systemd/system)
install(FILES ${generated}/tiltgate.1.gz DESTINATION share/man/man1)
# Run by the postinst: the web console's self-signed certificate (docs/web-console.md).
install(PROGRAMS ${packaging}/make-console-certificate DESTINATION libexec/tiltgate)
install(FILES ${packaging}/tiltgate.bash-completion DESTINATION share/bash-completion/completions
        RENAME tiltgate)
# The Wireshark dissectors of the buses' protocols, for the captures the gateway writes
# (`wireshark -X lua_script:/usr/share/tiltgate/tiltgate.lua`); not in Wireshark's plugin
# folder, so a gateway without Wireshark loads nothing.
install(FILES ${packaging}/wireshark/tiltgate.lua DESTINATION share/tiltgate)
install(FILES ${packaging}/copyright ${generated}/changelog.gz ${PROJECT_SOURCE_DIR}/README.md
        DESTINATION ${doc})
# The manual: every page of docs/ and the images the pages show, in a docs/ folder beside the
# README as in the source tree, so the README's relative links (docs/configuration.md, ...)
# and the pages' own links work in /usr/share/doc/tiltgate too. Not compressed, for the same
# reason: a link to page.md does not open page.md.gz. (Policy 12.3 says plain text
# documentation "should" be compressed unless small; Debian 12's lintian has no tag for it.)
file(GLOB manual_pages CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/docs/*.md
                                         ${PROJECT_SOURCE_DIR}/docs/*.png)
install(FILES ${manual_pages} DESTINATION ${doc}/docs)
install(FILES ${PROJECT_SOURCE_DIR}/examples/tiltgate.toml ${PROJECT_SOURCE_DIR}/examples/tiltgate-maps.toml
              ${PROJECT_SOURCE_DIR}/examples/builtin-maps.toml DESTINATION ${doc}/examples)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/maps ${PROJECT_SOURCE_DIR}/examples/devices
        DESTINATION ${doc}/examples)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME tiltgate)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_CONTACT "tiltgate maintainers <maintainers@users.noreply.h-seed-126b2148.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Modbus/TCP gateway for RS485 inclinometers")
# The extended description, in lines of at most 80 characters (CPack indents them for the
# control file).
set(CPACK_PACKAGE_DESCRIPTION
"A PLC or SCADA system connects over Modbus TCP and sees every configured
sensor as its own Modbus unit with a documented register map: angles, status,
counters and identity, read from a cache the gateway keeps fresh by polling
the RS485 buses (Rieker, Spectron and Modbus RTU inclinometers).
It runs as a hardened systemd service under its own system user.")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # tiltgate_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION net)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The libraries' packages from dpkg-shlibdeps; adduser for the postinst, openssl (the command)
# for the console's certificate it makes.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, openssl")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${packaging}/conffiles ${packaging}/postinst
    ${packaging}/prerm ${packaging}/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
