# lcm-spy: the Java classes decode what the C bindings encode (fingerprints
# and values), and lcm-spy itself, under Xvfb, lists the daemon's channels
# with our types. Needs the type jar (lcmtypes/java.cmake); the Xvfb test
# needs xvfb (skipped, exit 77, without it).
if(NOT TARGET wglcmtypes_java OR NOT WG_TYPES_JAR)
  return()
endif()
add_executable(wgenc wgenc.c)
target_link_libraries(wgenc PRIVATE wglcmtypes)
add_test(NAME clients.java_decode
         COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/test_java.sh decode $<TARGET_FILE:wgenc>
                 ${WG_TYPES_JAR} ${WG_LCM_JAR} ${Java_JAVAC_EXECUTABLE} ${Java_JAVA_EXECUTABLE}
                 ${CMAKE_CURRENT_SOURCE_DIR}/java)
set_tests_properties(clients.java_decode PROPERTIES TIMEOUT 60)
add_test(NAME clients.lcm_spy
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh sh ${CMAKE_CURRENT_SOURCE_DIR}/test_java.sh
                 spy $<TARGET_FILE:wormgeard> ${WG_TYPES_JAR} ${WG_LCM_JAR}
                 ${Java_JAVAC_EXECUTABLE} ${Java_JAVA_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/java
                 ${PROJECT_SOURCE_DIR}/clients/wgspy)
set_tests_properties(clients.lcm_spy PROPERTIES TIMEOUT 90 SKIP_RETURN_CODE 77
  ENVIRONMENT "WG_SCENE_PATH=${PROJECT_SOURCE_DIR}/scenes")
