# Java classes of the wormgear LCM types, for lcm-spy (issue 4): lcm-gen
# --java, javac against LCM's lcm.jar, one jar, installed beside Debian's
# jars (<prefix>/share/java/wormgear-lcmtypes.jar). Built only when a JDK and
# lcm.jar (Debian: default-jdk-headless, liblcm-java) are present.
find_package(Java 1.8 COMPONENTS Development QUIET)
find_file(WG_LCM_JAR lcm.jar PATHS /usr/share/java /usr/local/share/java NO_DEFAULT_PATH)
if(NOT Java_Development_FOUND OR NOT WG_LCM_JAR)
  message(STATUS "wormgear: no JDK or lcm.jar: the lcm-spy type jar is not built")
  return()
endif()

set(WG_JAVA_DIR ${CMAKE_CURRENT_BINARY_DIR}/java)
set(WG_JAVA_SRCS "")
foreach(t ${WG_LCM_TYPES})
  list(APPEND WG_JAVA_SRCS ${WG_JAVA_DIR}/src/wormgear/${t}.java)
endforeach()
set(WG_TYPES_JAR ${CMAKE_CURRENT_BINARY_DIR}/wormgear-lcmtypes.jar)
set(WG_TYPES_JAR ${WG_TYPES_JAR} PARENT_SCOPE)
set(WG_LCM_JAR ${WG_LCM_JAR} PARENT_SCOPE)

add_custom_command(
  OUTPUT ${WG_JAVA_SRCS}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${WG_JAVA_DIR}/src
  COMMAND ${LCM_GEN} --java --jpath ${WG_JAVA_DIR}/src ${WG_LCM_FILES}
  DEPENDS ${WG_LCM_FILES}
  COMMENT "lcm-gen: Java classes of the wormgear types"
  VERBATIM)
add_custom_command(
  OUTPUT ${WG_TYPES_JAR}
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${WG_JAVA_DIR}/classes
  COMMAND ${CMAKE_COMMAND} -E make_directory ${WG_JAVA_DIR}/classes
  COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -encoding UTF-8 --release 11 -cp ${WG_LCM_JAR}
          -d ${WG_JAVA_DIR}/classes ${WG_JAVA_SRCS}
  COMMAND ${Java_JAR_EXECUTABLE} cf ${WG_TYPES_JAR} -C ${WG_JAVA_DIR}/classes .
  DEPENDS ${WG_JAVA_SRCS}
  COMMENT "javac + jar: wormgear-lcmtypes.jar"
  VERBATIM)
add_custom_target(wglcmtypes_java ALL DEPENDS ${WG_TYPES_JAR})
install(FILES ${WG_TYPES_JAR} DESTINATION ${CMAKE_INSTALL_DATADIR}/java)
