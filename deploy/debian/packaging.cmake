# Debian packages with CPack (issue 22): `cpack -G DEB --config build/CPackConfig.cmake` (or
# tools/scripts/make_debs.sh) makes, for prefix /usr,
#   fleetloc-common      the fleetloc system user (postinst), /etc/fleetloc/cyclonedds.xml
#   fleetloc-map-server  map_server, its unit, /etc/fleetloc/map_server.json
#   fleetloc-supervisor  fleet_supervisor, the dashboard, its unit, /etc/fleetloc/fleet_supervisor.json
#   fleetloc-agent       tracker_agent, its unit template, /etc/fleetloc/tracker_agent.json (example)
#   fleetloc-tools       fleetctl, the docs, sample configurations, the DDS Security script
# Files under /etc/fleetloc are conffiles (an operator's edits survive upgrades). Library
# dependencies come from dpkg-shlibdeps; the rest are declared below. The units installed here are
# deploy/systemd's with the package paths (/usr/bin) and the loopback DDS configuration: a site
# that secures DDS points CYCLONEDDS_URI at its credentials with a drop-in (docs/operations.md).

set(deb_dir ${PROJECT_BINARY_DIR}/deb)
set(service_components map-server supervisor agent)
set(unit_map-server fleetloc-map-server.service)
set(unit_supervisor fleetloc-fleet-supervisor.service)
set(unit_agent fleetloc-tracker-agent@.service)
set(config_map-server map_server.json)
set(config_supervisor fleet_supervisor.json)
set(config_agent tracker_agent.json)

# The units for the packages, and each package's conffiles and maintainer scripts.
foreach(component ${service_components})
  set(unit ${unit_${component}})
  file(READ ${PROJECT_SOURCE_DIR}/deploy/systemd/${unit} text)
  string(REPLACE "/usr/local/bin/" "/usr/bin/" text "${text}")
  string(REPLACE "/usr/local/share/" "/usr/share/" text "${text}")
  string(REGEX REPLACE "Environment=CYCLONEDDS_URI=[^\n]*"
         "Environment=CYCLONEDDS_URI=file:///etc/fleetloc/cyclonedds.xml" text "${text}")
  file(WRITE ${deb_dir}/systemd/${unit} "${text}")
  install(FILES ${deb_dir}/systemd/${unit} DESTINATION /lib/systemd/system
          COMPONENT ${component} EXCLUDE_FROM_ALL)
  install(FILES ${PROJECT_SOURCE_DIR}/deploy/config/${config_${component}} DESTINATION /etc/fleetloc
          COMPONENT ${component} EXCLUDE_FROM_ALL)
  file(WRITE ${deb_dir}/${component}/conffiles "/etc/fleetloc/${config_${component}}\n")
  file(COPY ${PROJECT_SOURCE_DIR}/deploy/debian/postinst ${PROJECT_SOURCE_DIR}/deploy/debian/postrm
       DESTINATION ${deb_dir}/${component})
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/deploy/cyclonedds/loopback.xml DESTINATION /etc/fleetloc
        RENAME cyclonedds.xml COMPONENT common EXCLUDE_FROM_ALL)
file(WRITE ${deb_dir}/common/conffiles "/etc/fleetloc/cyclonedds.xml\n")
file(COPY ${PROJECT_SOURCE_DIR}/deploy/debian/postinst DESTINATION ${deb_dir}/common)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME fleetloc)
set(CPACK_PACKAGE_VENDOR "fleetloc")
set(CPACK_PACKAGE_CONTACT "fleetloc maintainers <fleetloc@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Fleet localization on floor texture")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL common map-server supervisor agent tools)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)  # fleetloc-common for every service
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_COMMON_PACKAGE_NAME fleetloc-common)
set(CPACK_DEBIAN_COMMON_PACKAGE_DEPENDS "adduser")
set(CPACK_DEBIAN_COMMON_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_COMMON_PACKAGE_CONTROL_EXTRA "${deb_dir}/common/conffiles;${deb_dir}/common/postinst")
set(CPACK_COMPONENT_COMMON_DESCRIPTION "fleetloc: the fleetloc system user and the DDS configuration\n The services of the other fleetloc packages run as this user.")
foreach(component ${service_components})
  string(TOUPPER ${component} upper)  # CPack's variable names keep the hyphen
  set(CPACK_DEBIAN_${upper}_PACKAGE_NAME fleetloc-${component})
  set(CPACK_DEBIAN_${upper}_PACKAGE_CONTROL_EXTRA
      "${deb_dir}/${component}/conffiles;${deb_dir}/${component}/postinst;${deb_dir}/${component}/postrm")
  set(CPACK_COMPONENT_${upper}_DEPENDS common)
endforeach()
set(CPACK_DEBIAN_SUPERVISOR_PACKAGE_DEPENDS "libjs-leaflet, libjs-chart.js")
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME fleetloc-tools)
set(CPACK_COMPONENT_MAP-SERVER_DESCRIPTION "fleetloc map server\n Serves the shared floor mosaic to the vehicles over DDS, collects their patches and re-maps.")
set(CPACK_COMPONENT_SUPERVISOR_DESCRIPTION "fleetloc fleet supervisor and dashboard\n Every vehicle's pose and health, alerts, history and the operators' web dashboard.")
set(CPACK_COMPONENT_AGENT_DESCRIPTION "fleetloc tracker agent\n Localizes one vehicle on the shared floor mosaic from its downward camera and odometry.")
set(CPACK_COMPONENT_TOOLS_DESCRIPTION "fleetloc command-line tools and documentation\n fleetctl: mosaics, offline tracking, simulation, calibration, fleet status.")
include(CPack)
