# wgrig: its point analysis against wg_point_run (no network), and a live
# sweep of the real daemon against the offline wgsweep at a few omega.
if(NOT TARGET wgrig)
  return()
endif()
add_executable(test_rig_point test_rig_point.c ${PROJECT_SOURCE_DIR}/clients/rig_point.c)
target_include_directories(test_rig_point PRIVATE ${PROJECT_SOURCE_DIR}/tests
                           ${PROJECT_SOURCE_DIR}/clients)
target_link_libraries(test_rig_point PRIVATE wormgear m)
add_test(NAME clients.rig_point COMMAND test_rig_point)
set_tests_properties(clients.rig_point PROPERTIES TIMEOUT 60)

add_test(NAME clients.wgrig
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/netns.sh sh ${CMAKE_CURRENT_SOURCE_DIR}/test_wgrig.sh
                 $<TARGET_FILE:wormgeard> $<TARGET_FILE:wgrig> $<TARGET_FILE:wgsweep>
                 $<TARGET_FILE:wgctl>)
set_tests_properties(clients.wgrig PROPERTIES TIMEOUT 90 ENVIRONMENT "${WGT_ENV}")
