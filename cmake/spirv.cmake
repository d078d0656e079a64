# Compiles a GLSL shader (compute, or a ray-tracing stage named by its extension) to SPIR-V at build time, validates it with spirv-val
# (the build fails on invalid SPIR-V), and embeds the words as a C array in
# ${MASQ_GENERATED_DIR}/spirv/<NAME>.h (`const uint32_t <NAME>[]`), which sources of
# TARGET include as "spirv/<NAME>.h". Header dependencies come from glslang's depfile.
#
#   masq_add_spirv(TARGET <target> SOURCE <file.comp> NAME <c_identifier>
#                  [VISIBILITY PUBLIC|PRIVATE] [DEFINES NAME=VALUE ...])
# DEFINES become glslang -D options (one source compiled into several modules).
include_guard(GLOBAL)

if(NOT GLSLANG_VALIDATOR)
  find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
endif()
if(NOT SPIRV_VAL)
  find_program(SPIRV_VAL spirv-val REQUIRED)
endif()
if(NOT MASQ_GENERATED_DIR)
  set(MASQ_GENERATED_DIR ${CMAKE_BINARY_DIR}/generated)
endif()

function(masq_add_spirv)
  cmake_parse_arguments(ARG "" "TARGET;SOURCE;NAME;VISIBILITY" "DEFINES" ${ARGN})
  if(NOT ARG_TARGET OR NOT ARG_SOURCE OR NOT ARG_NAME)
    message(FATAL_ERROR "masq_add_spirv: TARGET, SOURCE and NAME are required")
  endif()
  if(NOT ARG_VISIBILITY)
    set(ARG_VISIBILITY PRIVATE)
  endif()
  get_filename_component(src ${ARG_SOURCE} ABSOLUTE)
  set(out_dir ${MASQ_GENERATED_DIR}/spirv)
  set(spv ${out_dir}/${ARG_NAME}.spv)
  set(hdr ${out_dir}/${ARG_NAME}.h)
  set(glslang_args --target-env vulkan1.2 -V -I${CMAKE_SOURCE_DIR}/kernels)
  foreach(def IN LISTS ARG_DEFINES)
    list(APPEND glslang_args -D${def})
  endforeach()
  # The depfile's target is the .spv (the first output), as Ninja requires.
  add_custom_command(
    OUTPUT ${spv} ${hdr}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
    COMMAND ${GLSLANG_VALIDATOR} ${glslang_args} --depfile ${spv}.d -o ${spv} ${src}
    COMMAND ${SPIRV_VAL} --target-env vulkan1.2 ${spv}
    COMMAND ${GLSLANG_VALIDATOR} ${glslang_args} --vn ${ARG_NAME} -o ${hdr} ${src}
    MAIN_DEPENDENCY ${src}
    DEPFILE ${spv}.d
    COMMENT "GLSL -> SPIR-V ${ARG_NAME} (glslang, spirv-val)"
    VERBATIM)
  target_sources(${ARG_TARGET} PRIVATE ${hdr})
  # Every module of a target, for the checks that read them all (tests/CMakeLists.txt:
  # MASQ_SPIRV_MODULES_masq_vulkan are the shipped kernels).
  set_property(GLOBAL APPEND PROPERTY MASQ_SPIRV_MODULES_${ARG_TARGET} ${spv})
  target_include_directories(${ARG_TARGET} ${ARG_VISIBILITY} ${MASQ_GENERATED_DIR})
endfunction()
