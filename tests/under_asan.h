#pragma once
// UASCMA_UNDER_ASAN is defined when the test is compiled with AddressSanitizer (GCC's __SANITIZE_ADDRESS__, clang's
// __has_feature(address_sanitizer)): for tests that must not interpose malloc or limit the address space there.
#if defined(__SANITIZE_ADDRESS__)
#define UASCMA_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UASCMA_UNDER_ASAN 1
#endif
#endif
