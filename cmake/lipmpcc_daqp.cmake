# lipmpcc_daqp: DAQP 0.11.0, vendored C (MIT, cpp/third_party/daqp/README.md), as a static library with
# upstream's own optimisation flags (its Python wheel's), warnings off (not our code). Hidden symbols:
# the modules do not export DAQP's (the daqp Python package may load another DAQP). Defined once, by
# the first of cpp/wbc and cpp/sqp that needs it.
if(TARGET lipmpcc_daqp)
  return()
endif()
file(GLOB _daqp_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/../cpp/third_party/daqp/src/*.c)
add_library(lipmpcc_daqp STATIC ${_daqp_sources})
target_include_directories(lipmpcc_daqp SYSTEM PUBLIC ${CMAKE_CURRENT_LIST_DIR}/../cpp/third_party/daqp/include)
target_compile_options(lipmpcc_daqp PRIVATE -O3 -w -fassociative-math -fno-signed-zeros -fno-trapping-math)
find_library(_libm m)
if(_libm)
  target_link_libraries(lipmpcc_daqp PRIVATE ${_libm})
endif()
set_target_properties(lipmpcc_daqp PROPERTIES POSITION_INDEPENDENT_CODE ON C_STANDARD 99 C_VISIBILITY_PRESET hidden)
