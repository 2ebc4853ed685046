# cython: language_level=3
"""The SDF reader's kinematic elements: one pass of expat that builds an ``xml.etree`` tree of only them.

The SDF reader (``robkin.io.sdf``) reads the root, its ``<world>``s and ``<model>``s, a model's
``<link>``, ``<frame>``, ``<model>``, ``<joint>``, ``<include>`` and ``<pose>`` children, a link's or
frame's ``<pose>``, a joint's ``<parent>``, ``<child>``, ``<pose>`` and ``<axis>``, and in the axis
``<xyz>``, ``<use_parent_model_frame>``, ``<limit>`` (``lower``, ``upper``, ``effort``, ``velocity``) and
``<dynamics>`` (``damping``, ``friction``). ``kinematic_tree`` keeps exactly these elements, with their
attributes, and the text of those the reader reads text from, as ``xml.etree`` would give them (tags
and attributes in a namespace as "{uri}local"), as ``Kept`` elements: the part of ``xml.etree``'s
Element API the reader calls (``tag``, ``text``, ``get``, ``find``, ``findall``, ``findtext`` with a
plain tag), each one C struct. Everything else (visuals, collisions, inertials, sensors, plugins: most
of a file) is skipped without an element or a string made for it. The link contents are parsed from
the text later, only when asked for (``robkin.io.sdf.shapes``).

The standard library's own expat is reached through the ``pyexpat.expat_CAPI`` capsule (see
``urdf_scan``) and driven as ``xml.etree.ElementTree.XMLParser.feed`` drives it for a string (UTF-8,
one call, then the final one), so a file that is not well-formed is refused at the same line and column.
"""

cimport cython
from cpython.unicode cimport PyUnicode_DecodeUTF8
from libc.string cimport strcmp, strlen

from robkin.compiled.scanners.expat_capi cimport (XML_Parser, PyExpat_CAPI, expat_capi)
from robkin.errors import InputError

cdef extern from "Python.h":
    const char* PyUnicode_AsUTF8AndSize(object text, Py_ssize_t* size) except NULL

cdef PyExpat_CAPI* _capi = expat_capi(b"robkin.compiled.scanners.sdf_scan")

# what an element is to the reader (its parent's kind and its tag decide; see _kind)
cdef enum:
    SKIP = 0    # not read: neither it nor anything in it is kept
    ROOT = 1
    WORLD = 2
    MODEL = 3
    LINK = 4    # <link> and <frame>: only their <pose> is read
    JOINT = 5
    AXIS = 6
    LIMIT = 7
    DYNAMICS = 8
    EMPTY = 9   # kept for its attributes only (<include>)
    TEXT = 10   # kept with its text (<pose>, <parent>, <xyz>, <lower>...)


cdef inline bint _is(const char* tag, const char* name) noexcept:
    return strcmp(tag, name) == 0


cdef int _kind(int parent, const char* tag) noexcept:
    """The kind of an element ``tag`` (expat's name: "uri}local" in a namespace) in one of ``parent``."""
    if parent == ROOT:
        return MODEL if _is(tag, b"model") else WORLD if _is(tag, b"world") else SKIP
    if parent == WORLD:
        return MODEL if _is(tag, b"model") else SKIP
    if parent == MODEL:
        if _is(tag, b"link") or _is(tag, b"frame"):
            return LINK
        if _is(tag, b"joint"):
            return JOINT
        if _is(tag, b"model"):
            return MODEL
        if _is(tag, b"pose"):
            return TEXT
        return EMPTY if _is(tag, b"include") else SKIP
    if parent == LINK:
        return TEXT if _is(tag, b"pose") else SKIP
    if parent == JOINT:
        if _is(tag, b"pose") or _is(tag, b"parent") or _is(tag, b"child"):
            return TEXT
        return AXIS if _is(tag, b"axis") else SKIP
    if parent == AXIS:
        if _is(tag, b"xyz") or _is(tag, b"use_parent_model_frame"):
            return TEXT
        return LIMIT if _is(tag, b"limit") else DYNAMICS if _is(tag, b"dynamics") else SKIP
    if parent == LIMIT:
        return TEXT if (_is(tag, b"lower") or _is(tag, b"upper") or _is(tag, b"effort")
                        or _is(tag, b"velocity")) else SKIP
    if parent == DYNAMICS:
        return TEXT if _is(tag, b"damping") or _is(tag, b"friction") else SKIP
    return SKIP


@cython.final
@cython.no_gc  # holds strings, a dict of strings and elements below it: a tree, no cycles
cdef class Kept:
    """One element kept by ``kinematic_tree``: what the SDF reader asks of an ``xml.etree`` Element."""
    cdef readonly str tag
    cdef public object text  # None: no text (or not kept: only TEXT elements keep theirs)
    cdef dict attrib         # None: no attributes
    cdef list children       # None: no children kept

    def get(self, str key, default=None):
        return default if self.attrib is None else self.attrib.get(key, default)

    def find(self, str tag):
        """The first child called ``tag``, or None."""
        cdef Kept c
        if self.children is not None:
            for c in self.children:
                if c.tag == tag:
                    return c
        return None

    def findall(self, str tag):
        """The children called ``tag``, in file order."""
        cdef Kept c
        return [] if self.children is None else [c for c in self.children if c.tag == tag]

    def findtext(self, str tag, default=None):
        """The text of the first child called ``tag`` ("" if it has none), else ``default``."""
        c = self.find(tag)
        if c is None:
            return default
        return "" if c.text is None else c.text


cdef class _Tree:
    """What the callbacks keep while expat runs: the kept elements open now, their kinds, the text."""
    cdef list open, kinds
    cdef Kept root
    cdef object error
    cdef Py_ssize_t skipped  # depth inside a skipped element (0: not in one)
    cdef list text           # pieces of the text of the open TEXT element, until its first child
    cdef bint collecting


cdef inline object _name(const char* s):
    """expat's "uri}local" as xml.etree writes it, "{uri}local"."""
    cdef object name = PyUnicode_DecodeUTF8(s, strlen(s), NULL)
    return "{" + name if "}" in name else name


cdef void _flush(_Tree t) except *:
    if t.collecting:
        t.collecting = False
        if t.text:
            t.open[len(t.open) - 1].text = "".join(t.text)
            t.text = []


cdef void _start(void* data, const char* tag, const char** atts) noexcept:
    cdef _Tree t = <_Tree>data
    cdef int kind
    cdef Py_ssize_t i = 0
    cdef Kept el, parent
    if t.error is not None:
        return
    if t.skipped:
        t.skipped += 1
        return
    try:
        _flush(t)  # a child ends its parent's text (xml.etree: the text is what precedes the first child)
        kind = ROOT if t.root is None else _kind(t.kinds[len(t.kinds) - 1], tag)
        if kind == SKIP:
            t.skipped = 1
            return
        el = Kept.__new__(Kept)
        el.tag = _name(tag)
        if atts[0] != NULL:
            el.attrib = {}
            while atts[i] != NULL:
                el.attrib[_name(atts[i])] = PyUnicode_DecodeUTF8(atts[i + 1], strlen(atts[i + 1]), NULL)
                i += 2
        if t.root is None:
            t.root = el
        else:
            parent = <Kept>t.open[len(t.open) - 1]
            if parent.children is None:
                parent.children = [el]
            else:
                parent.children.append(el)
        t.open.append(el)
        t.kinds.append(kind)
        t.collecting = kind == TEXT
    except BaseException as exc:  # a MemoryError: kept, raised once expat has returned
        t.error = exc


cdef void _end(void* data, const char* tag) noexcept:
    cdef _Tree t = <_Tree>data
    if t.error is not None:
        return
    if t.skipped:
        t.skipped -= 1
        return
    try:
        _flush(t)
        t.open.pop()
        t.kinds.pop()
    except BaseException as exc:
        t.error = exc


cdef void _data(void* data, const char* s, int n) noexcept:
    cdef _Tree t = <_Tree>data
    if t.collecting and not t.skipped and t.error is None:
        try:
            t.text.append(PyUnicode_DecodeUTF8(s, n, NULL))
        except BaseException as exc:
            t.error = exc


def kinematic_tree(str text, str src):
    """Root element of SDF text with only the elements the SDF reader reads (see the module's
    docstring); InputError "not well-formed XML (line, column)" or "not valid XML (...)" as
    ``robkin.io.trees.xml_parse._parse_xml`` words them (the caller refuses DTDs first, as that does)."""
    cdef Py_ssize_t n
    cdef const char* b
    try:
        b = PyUnicode_AsUTF8AndSize(text, &n)
    except UnicodeError as exc:  # a lone surrogate in a Python string
        raise InputError(f"{src}: not valid XML ({exc})") from None
    if n > 0x7fffffff:
        raise InputError(f"{src}: not valid XML (more than 2 GB)")
    cdef _Tree t = _Tree()
    t.open, t.kinds, t.text = [], [], []
    cdef XML_Parser p = _capi.ParserCreate_MM(b"utf-8", NULL, b"}")
    if p == NULL:
        raise MemoryError()
    cdef int ok
    cdef unsigned long line = 0, column = 0
    try:
        _capi.SetUserData(p, <void*>t)
        _capi.SetElementHandler(p, _start, _end)
        _capi.SetCharacterDataHandler(p, _data)
        ok = _capi.Parse(p, b, <int>n, 0) and t.error is None and _capi.Parse(p, b"", 0, 1)
        if not ok and t.error is None:
            line, column = _capi.GetErrorLineNumber(p), _capi.GetErrorColumnNumber(p)
    finally:
        _capi.ParserFree(p)
    if t.error is not None:
        raise t.error
    if not ok:
        raise InputError(f"{src}: not well-formed XML (line {line}, column {column + 1})")
    return t.root
