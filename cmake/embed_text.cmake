# cmake -DINPUT=<text file> -DOUTPUT=<file.cc> -DNAMESPACE=<ns> -DSYMBOL=<name>
#       -P embed_text.cmake
# Writes a C++ source defining `const char <NAMESPACE>::<SYMBOL>[]` holding the
# text of INPUT byte for byte, as a raw string literal, so a text file of the
# tree (config/default.ini) is compiled into the program that documents it.
foreach(_var INPUT OUTPUT NAMESPACE SYMBOL)
  if(NOT DEFINED ${_var})
    message(FATAL_ERROR "embed_text.cmake: -D${_var}=... is required")
  endif()
endforeach()
file(READ "${INPUT}" _text)
set(_delim "hmt_text")  # at most 16 characters (C++)
string(FIND "${_text}" ")${_delim}\"" _clash)
if(NOT _clash EQUAL -1)
  message(FATAL_ERROR "embed_text.cmake: ${INPUT} holds the raw string delimiter ${_delim}")
endif()
file(RELATIVE_PATH _shown "${CMAKE_CURRENT_LIST_DIR}/.." "${INPUT}")
set(_source "// Generated from ${_shown} by cmake/embed_text.cmake; do not edit.
namespace ${NAMESPACE} {
extern const char ${SYMBOL}[];
const char ${SYMBOL}[] = R\"${_delim}(${_text})${_delim}\";
}  // namespace ${NAMESPACE}
")
# Rewritten only when it changes, so that an unchanged text rebuilds nothing.
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" _old)
  if(_old STREQUAL _source)
    return()
  endif()
endif()
file(WRITE "${OUTPUT}" "${_source}")
