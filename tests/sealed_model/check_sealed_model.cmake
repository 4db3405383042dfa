# Checks that a CollisionModel cannot be changed from outside (issue "API II"):
# tests/sealed_model/edits.cpp compiled with -fsyntax-only against the public
# headers once per EDIT. EDIT=0 (reading the model) must compile, so that the
# others cannot pass because the compile is broken for another reason; every
# edit must fail, with a diagnostic matching its pattern (the edit itself
# refused, not a typo in it).
# The compiles run at once (sh, in the background), each writing its
# diagnostics to WORK_DIR/EDIT.log and its exit code to WORK_DIR/EDIT.rc.
# Run by ctest: cmake -DCXX=<compiler> -DINCLUDES=<dir;dir> -DSOURCE=<edits.cpp> -DWORK_DIR=<dir>
#   -P this file.
# EDIT number, what it tries, what its diagnostic must name.
set(edits
  "1|model.vertices.push_back(...)|vertices"
  "2|model.vertices().push_back(...)|push_back"
  "3|model.polygons()[0].plane = {}|const|read-only"
  "4|model.arrays().vertices.push_back(...)|const|discards|push_back"
  "5|CollisionModel m (no public default constructor)|CollisionModel"
  "6|CollisionModel m(ModelArrays{}) (private constructor)|private|CollisionModel"
  "7|CollisionModel m{ModelArrays{}} (private constructor)|private|CollisionModel")
list(LENGTH edits kNumEdits)
set(flags "-std=c++20 -fsyntax-only")
foreach(dir IN LISTS INCLUDES)
  string(APPEND flags " '-I${dir}'")
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(script "")
foreach(edit RANGE ${kNumEdits})
  string(APPEND script "('${CXX}' ${flags} -DEDIT=${edit} '${SOURCE}' >'${WORK_DIR}/${edit}.log' 2>&1; "
                       "echo $? >'${WORK_DIR}/${edit}.rc') &\n")
endforeach()
string(APPEND script "wait\n")
execute_process(COMMAND sh -c "${script}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sh failed (${rc}) running the compiles")
endif()

function(compile edit result_var output_var)
  file(READ ${WORK_DIR}/${edit}.rc rc)
  string(STRIP "${rc}" rc)
  file(READ ${WORK_DIR}/${edit}.log out)
  set(${result_var} ${rc} PARENT_SCOPE)
  set(${output_var} "${out}" PARENT_SCOPE)
endfunction()

compile(0 rc out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the control (EDIT=0, reading the model) does not compile:\n${out}")
endif()

set(failed "")
foreach(entry IN LISTS edits)
  string(REPLACE "|" ";" parts "${entry}")
  list(POP_FRONT parts edit what)
  list(JOIN parts "|" pattern)
  compile(${edit} rc out)
  if(rc EQUAL 0)
    string(APPEND failed "  EDIT=${edit} compiles: ${what}\n")
  elseif(NOT out MATCHES "${pattern}")
    string(APPEND failed "  EDIT=${edit} fails for another reason than ${what} (no '${pattern}'):\n${out}\n")
  else()
    message(STATUS "refused as it should be: ${what}")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "a CollisionModel can be changed from outside:\n${failed}")
endif()
