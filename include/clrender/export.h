/* CLR_API marks the library's exported functions; everything else in libclrender is hidden. */
#ifndef CLRENDER_EXPORT_H
#define CLRENDER_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define CLR_API __attribute__((visibility("default")))
#else
#define CLR_API
#endif

#endif
