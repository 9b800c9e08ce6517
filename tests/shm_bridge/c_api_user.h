/* The C side of c_api_test.cc (c_api_user.c). */
#pragma once
#include <stddef.h>
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif
int c_controller(const char* segment, int cycles);
int c_refusals(const char* missing_segment, char* err, size_t errlen);
int c_observer(const char* segment, uint64_t* last_cycle);
#ifdef __cplusplus
}
#endif
