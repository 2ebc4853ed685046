# cython: language_level=3
"""The standard library's expat, as the compiled XML scans (``urdf_scan``, ``sdf_scan``) reach it: the
``pyexpat.expat_CAPI`` capsule (``xml.etree``'s C accelerator reaches it the same way), checked once."""

from cpython.pycapsule cimport PyCapsule_Import
from libc.string cimport strcmp

cdef extern from "scanners/expat_shim.h":
    ctypedef void* XML_Parser
    ctypedef void (*XML_StartElementHandler)(void*, const char*, const char**) noexcept
    ctypedef void (*XML_EndElementHandler)(void*, const char*) noexcept
    ctypedef void (*XML_CharacterDataHandler)(void*, const char*, int) noexcept
    ctypedef void (*XML_StartDoctypeDeclHandler)(void*, const char*, const char*, const char*, int) noexcept
    const char* PyExpat_CAPI_MAGIC
    struct PyExpat_CAPI:
        char* magic
        int size
        unsigned long (*GetErrorColumnNumber)(XML_Parser parser)
        unsigned long (*GetErrorLineNumber)(XML_Parser parser)
        int (*Parse)(XML_Parser parser, const char* s, int len, int isFinal)
        XML_Parser (*ParserCreate_MM)(const char* encoding, const void* memsuite, const char* sep)
        void (*ParserFree)(XML_Parser parser)
        void (*SetCharacterDataHandler)(XML_Parser parser, XML_CharacterDataHandler handler)
        void (*SetElementHandler)(XML_Parser parser, XML_StartElementHandler start, XML_EndElementHandler end)
        void (*SetUserData)(XML_Parser parser, void* userData)
        void (*SetStartDoctypeDeclHandler)(XML_Parser parser, XML_StartDoctypeDeclHandler start)


cdef inline PyExpat_CAPI* expat_capi(const char* module) except NULL:
    """This Python's expat capsule; ImportError naming ``module`` if it is not the layout built for."""
    cdef PyExpat_CAPI* capi = <PyExpat_CAPI*>PyCapsule_Import(b"pyexpat.expat_CAPI", 0)
    if strcmp(capi.magic, PyExpat_CAPI_MAGIC) != 0 or <size_t>capi.size < sizeof(PyExpat_CAPI):
        raise ImportError(f"{module.decode('ascii')}: this Python's pyexpat capsule is "
                          f"'{capi.magic.decode('ascii', 'replace')}' of {capi.size} bytes; the module was built for "
                          f"'{PyExpat_CAPI_MAGIC.decode('ascii')}' of {sizeof(PyExpat_CAPI)} bytes: rebuild it "
                          f"(pip install -e . or make ext)")
    return capi
