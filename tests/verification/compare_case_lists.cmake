# Fails when `talus verify --list --tier TIER` names a case that has no ctest (or a ctest names a
# case the tier does not have): every case of a tier must run in the suite.
#   cmake -DTALUS=<talus> -DTIER=<tier> -DEXPECTED=a,b,c -P compare_case_lists.cmake
execute_process(COMMAND ${TALUS} verify --list --tier ${TIER}
                OUTPUT_VARIABLE listed RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "talus verify --list --tier ${TIER} exited with ${status}")
endif()
string(STRIP "${listed}" listed)
string(REPLACE "\n" ";" listed "${listed}")
if(listed STREQUAL "")
  message(FATAL_ERROR "talus verify --list --tier ${TIER} listed no case")
endif()
list(SORT listed)
string(REPLACE "," ";" expected "${EXPECTED}")
list(SORT expected)
set(missing ${listed})
list(REMOVE_ITEM missing ${expected})
set(unknown ${expected})
list(REMOVE_ITEM unknown ${listed})
if(missing OR unknown)
  message(FATAL_ERROR "tier ${TIER}: cases without a ctest: '${missing}'; "
                      "ctests of no case in the tier: '${unknown}'")
endif()
list(LENGTH listed count)
message(STATUS "tier ${TIER}: each of the ${count} cases has a ctest")
