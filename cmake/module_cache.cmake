# A content-addressed cache of the installed compiled modules (lipmpcc._wbc, lipmpcc._mjtick).
#
# pip builds every `pip install .` in a fresh isolated environment, so the dependencies' headers sit
# under a new /tmp/pip-build-env-* path each time and CMake's own incremental build recompiles
# everything (about 2.5 min on 2 cores), e.g. for the README's second command after the first. The
# modules as installed (RPATHs rewritten) are kept under build/module-cache/KEY, where KEY is a SHA-256
# over everything that goes into them: every file under cpp/, the CMake files, the compiler and its
# flags, the Python ABI and the versions of the build dependencies. A build whose KEY is cached installs
# those files and compiles nothing. LIPMPCC_NO_MODULE_CACHE=1 in the environment turns the cache off.

# lipmpcc_module_cache_key(OUT_VAR SOURCE_DIR EXTRA...): KEY over SOURCE_DIR/cpp/**, SOURCE_DIR/cmake/**,
# SOURCE_DIR/CMakeLists.txt and the EXTRA strings.
function(lipmpcc_module_cache_key out_var source_dir)
  file(GLOB_RECURSE _files RELATIVE "${source_dir}"
       "${source_dir}/cpp/*" "${source_dir}/cmake/*" "${source_dir}/CMakeLists.txt")
  list(SORT _files)
  set(_acc "lipmpcc-module-cache-v1")
  foreach(_f IN LISTS _files)
    file(SHA256 "${source_dir}/${_f}" _h)
    string(APPEND _acc "\n${_f}=${_h}")
  endforeach()
  foreach(_e IN LISTS ARGN)
    string(APPEND _acc "\n${_e}")
  endforeach()
  string(SHA256 _key "${_acc}")
  set(${out_var} "${_key}" PARENT_SCOPE)
endfunction()

# lipmpcc_cached_modules(OUT_VAR CACHE_DIR): the module files of a complete cache entry (one whose
# MANIFEST lists files that all exist), else an empty list.
function(lipmpcc_cached_modules out_var cache_dir)
  set(_found "")
  if(EXISTS "${cache_dir}/MANIFEST")
    file(STRINGS "${cache_dir}/MANIFEST" _names)
    set(_found "")
    foreach(_n IN LISTS _names)
      if(NOT EXISTS "${cache_dir}/${_n}")
        set(_found "")
        break()
      endif()
      list(APPEND _found "${cache_dir}/${_n}")
    endforeach()
  endif()
  set(${out_var} "${_found}" PARENT_SCOPE)
endfunction()

# lipmpcc_store_modules(CACHE_DIR): an install-time step that copies the just-installed modules
# (PREFIX/lipmpcc/_*.so|.pyd|.dylib) into CACHE_DIR, atomically (a partial folder renamed at the end).
function(lipmpcc_store_modules cache_dir)
  install(CODE "
    set(_dst \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lipmpcc\")
    file(GLOB _mods \"\${_dst}/_*.so\" \"\${_dst}/_*.pyd\" \"\${_dst}/_*.dylib\")
    if(_mods AND NOT EXISTS \"${cache_dir}/MANIFEST\")
      string(RANDOM LENGTH 8 _r)
      set(_tmp \"${cache_dir}.partial-\${_r}\")
      file(MAKE_DIRECTORY \"\${_tmp}\")
      set(_names \"\")
      foreach(_m IN LISTS _mods)
        file(COPY \"\${_m}\" DESTINATION \"\${_tmp}\")
        get_filename_component(_n \"\${_m}\" NAME)
        string(APPEND _names \"\${_n}\\n\")
      endforeach()
      file(WRITE \"\${_tmp}/MANIFEST\" \"\${_names}\")
      file(REMOVE_RECURSE \"${cache_dir}\")
      file(RENAME \"\${_tmp}\" \"${cache_dir}\")
      message(STATUS \"lipmpcc: compiled modules kept in ${cache_dir}\")
    endif()
  ")
endfunction()
