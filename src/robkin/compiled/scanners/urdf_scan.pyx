# cython: language_level=3
"""The URDF reader's core: one pass of expat over the text that keeps only the kinematic tree.

The standard library's own expat (reached through the ``pyexpat.expat_CAPI`` capsule, as
``xml.etree``'s C accelerator reaches it) calls two C callbacks per element; they copy the attributes
of the root, of each top-level ``<link>`` (its name) and of each top-level ``<joint>`` and its first
``<parent>``, ``<child>``, ``<origin>``, ``<axis>``, ``<limit>``, ``<dynamics>`` and ``<mimic>``
children, and nothing else: no tree is built. Everything else (link contents, materials, extensions) is
parsed from the text later, only when asked for (``robkin.io.urdf.content``).

Tags are namespace-aware exactly as in ``xml.etree`` ("{uri}local"), so the scan and the lazy content
parse agree on what a tag is: an element in a namespace (a default ``xmlns`` included) is not a URDF
element (urdfdom ignores namespaces, so it reads a ``<robot xmlns="...">`` that is refused here, by name).
The attributes' numbers are read by ``attribute_numbers`` (the same functions serve every reader).
"""

cimport cython
from cpython.unicode cimport PyUnicode_DecodeUTF8
from libc.string cimport strcmp, strlen, strncmp
from robkin.compiled.scanners.attribute_numbers cimport number, numbers
from robkin.compiled.scanners.expat_capi cimport PyExpat_CAPI, XML_Parser, expat_capi

import os.path

from robkin.errors import InputError, quote
from robkin.compiled.scanners.vocabulary import NO_LIMIT, SUPPORTED_TYPES, UNSUPPORTED_TYPES

cdef extern from "Python.h":
    const char* PyUnicode_AsUTF8AndSize(object text, Py_ssize_t* size) except NULL

cdef PyExpat_CAPI* _capi = expat_capi(b"robkin.compiled.scanners.urdf_scan")

#: Deepest element nesting accepted: libxml2's default limit (which lxml, used for the lazy content
#: parse of big files, applies too); a URDF nests ~5 deep. Bounds expat's tag stack on hostile input.
cdef enum:
    _MAX_DEPTH = 256
MAX_DEPTH = _MAX_DEPTH
# how expat names an element in xacro's namespace ("uri}local": separator '}', as xml.etree asks for)
cdef const char* _XACRO_TAG = b"http://www.ros.org/wiki/xacro}"
cdef size_t _XACRO_TAG_LEN = strlen(_XACRO_TAG)
#: Bytes handed to expat at a time: between pieces the scan stops at the first refusal (too deep).
_CHUNK = 1 << 20
_ZERO3 = (0.0, 0.0, 0.0)
_X_AXIS = (1.0, 0.0, 0.0)  # URDF's default joint axis

# bits of the first children of a <joint> already seen (the first of each counts, as in urdfdom)
cdef enum:
    SEEN_PARENT = 1
    SEEN_CHILD = 2
    SEEN_ORIGIN = 4
    SEEN_AXIS = 8
    SEEN_LIMIT = 16
    SEEN_DYNAMICS = 32
    SEEN_MIMIC = 64


cdef object _limit(text, where, what):
    """A joint limit; None (no limit on that side) at +-inf or beyond +-NO_LIMIT, as written out."""
    v = number(text, where, what, True)
    return v if v is not None and abs(v) < NO_LIMIT else None


# ------------------------------------------------------------------------------------------ the scan
@cython.no_gc  # holds only strings and None: no cycles, so the collector need not track it
cdef class _Joint:
    """The attributes of one <joint> and of its first children, as the file wrote them (or None)."""
    cdef object name, type, parent, child, xyz, rpy, axis
    cdef object lower, upper, effort, velocity, damping, friction, mimic, multiplier, offset
    cdef int seen


cdef class _Scan:
    """What the callbacks keep while expat runs (their user data): depth, links, joints, refusals."""
    cdef int depth
    cdef bint xacro, doctype, too_deep
    cdef object root_tag, robot_name, error
    cdef list links, joints
    cdef _Joint joint  # the <joint> being read, None outside one


cdef inline object _text(const char* s):
    return PyUnicode_DecodeUTF8(s, strlen(s), NULL)


cdef object _attr(const char** atts, const char* key):
    """The value of attribute ``key`` (None if absent)."""
    cdef Py_ssize_t i = 0
    while atts[i] != NULL:
        if strcmp(atts[i], key) == 0:
            return _text(atts[i + 1])
        i += 2
    return None


cdef void _joint_child(_Joint j, const char* tag, const char** atts) except *:
    """Copy what a <joint>'s child says, if it is the first of its tag."""
    if strcmp(tag, b"parent") == 0 and not j.seen & SEEN_PARENT:
        j.seen |= SEEN_PARENT
        j.parent = _attr(atts, b"link")
    elif strcmp(tag, b"child") == 0 and not j.seen & SEEN_CHILD:
        j.seen |= SEEN_CHILD
        j.child = _attr(atts, b"link")
    elif strcmp(tag, b"origin") == 0 and not j.seen & SEEN_ORIGIN:
        j.seen |= SEEN_ORIGIN
        j.xyz, j.rpy = _attr(atts, b"xyz"), _attr(atts, b"rpy")
    elif strcmp(tag, b"axis") == 0 and not j.seen & SEEN_AXIS:
        j.seen |= SEEN_AXIS
        j.axis = _attr(atts, b"xyz")
    elif strcmp(tag, b"limit") == 0 and not j.seen & SEEN_LIMIT:
        j.seen |= SEEN_LIMIT
        j.lower, j.upper = _attr(atts, b"lower"), _attr(atts, b"upper")
        j.effort, j.velocity = _attr(atts, b"effort"), _attr(atts, b"velocity")
    elif strcmp(tag, b"dynamics") == 0 and not j.seen & SEEN_DYNAMICS:
        j.seen |= SEEN_DYNAMICS
        j.damping, j.friction = _attr(atts, b"damping"), _attr(atts, b"friction")
    elif strcmp(tag, b"mimic") == 0 and not j.seen & SEEN_MIMIC:
        j.seen |= SEEN_MIMIC
        j.mimic, j.multiplier, j.offset = _attr(atts, b"joint"), _attr(atts, b"multiplier"), _attr(atts, b"offset")


cdef void _start(void* data, const char* tag, const char** atts) noexcept:
    cdef _Scan s = <_Scan>data
    cdef _Joint j
    if s.error is not None or s.too_deep:
        return
    s.depth += 1
    try:
        if tag[0] == c'h' and strncmp(tag, _XACRO_TAG, _XACRO_TAG_LEN) == 0:
            s.xacro = True
        if s.depth == 3 and s.joint is not None:
            _joint_child(s.joint, tag, atts)
        elif s.depth == 2:
            if strcmp(tag, b"link") == 0:
                s.links.append(_attr(atts, b"name"))
            elif strcmp(tag, b"joint") == 0:
                j = _Joint()
                j.name, j.type = _attr(atts, b"name"), _attr(atts, b"type")
                s.joints.append(j)
                s.joint = j
        elif s.depth == 1:
            s.root_tag, s.robot_name = _text(tag), _attr(atts, b"name")
        elif s.depth > _MAX_DEPTH:
            s.too_deep = True
    except BaseException as exc:  # a MemoryError: kept, raised once expat has returned
        s.error = exc


cdef void _end(void* data, const char* tag) noexcept:
    cdef _Scan s = <_Scan>data
    if s.depth == 2:
        s.joint = None
    s.depth -= 1


cdef void _doctype(void* data, const char* name, const char* sysid, const char* pubid, int internal) noexcept:
    (<_Scan>data).doctype = True


cdef _Scan _run(str text, str src):
    """Scan ``text`` with expat; InputError if it is not well-formed, has a DTD or nests too deep."""
    cdef Py_ssize_t n, at = 0, piece
    cdef const char* b
    try:
        b = PyUnicode_AsUTF8AndSize(text, &n)
    except UnicodeError as exc:  # a lone surrogate in a Python string
        raise InputError(f"{src}: not valid XML ({exc})") from None
    cdef _Scan s = _Scan()
    s.links, s.joints = [], []
    cdef XML_Parser p = _capi.ParserCreate_MM(b"utf-8", NULL, b"}")
    if p == NULL:
        raise MemoryError()
    cdef int ok = 1
    cdef unsigned long line = 0, column = 0
    try:
        _capi.SetUserData(p, <void*>s)
        _capi.SetElementHandler(p, _start, _end)
        _capi.SetStartDoctypeDeclHandler(p, _doctype)
        while ok:
            piece = min(n - at, _CHUNK)
            ok = _capi.Parse(p, b + at, <int>piece, at + piece == n)
            at += piece
            if at == n or s.error is not None or s.too_deep or s.doctype:
                break
        if not ok:
            line, column = _capi.GetErrorLineNumber(p), _capi.GetErrorColumnNumber(p)
    finally:
        _capi.ParserFree(p)
    if s.error is not None:
        raise s.error
    if s.doctype:
        raise InputError(f"{src}: refused XML construct (a DTD or entity declaration); a URDF needs no DTD, "
                         f"entities or external references")
    if s.too_deep:
        raise InputError(f"{src}: elements nest more than {MAX_DEPTH} deep; a URDF nests a few levels")
    if not ok:
        raise InputError(f"{src}: not well-formed XML (line {line}, column {column + 1})")
    return s


cdef object _joint(_Joint raw, str src, Py_ssize_t index, object joint_type, object mimic_type):
    """One joint, every attribute checked (the numbers stay plain floats: see UrdfJoint), as a
    ``joint_type`` (with a ``mimic_type`` for its <mimic>)."""
    name = raw.name
    if not name:
        raise InputError(f"{src}: joint #{index + 1} has no name attribute")
    where = f"{src}: joint '{name}'"
    jtype = raw.type
    if jtype not in SUPPORTED_TYPES:
        if jtype is None:
            raise InputError(f"{where}: no type attribute; one of {', '.join(SUPPORTED_TYPES)}")
        if jtype not in UNSUPPORTED_TYPES:
            raise InputError(f"{where}: unknown type {quote(jtype)}; one of "
                             f"{', '.join(SUPPORTED_TYPES + UNSUPPORTED_TYPES)}")
    if not raw.parent:
        raise InputError(f"{where}: missing <parent link=\"...\"/>")
    if not raw.child:
        raise InputError(f"{where}: missing <child link=\"...\"/>")
    xyz_rpy = (numbers(raw.xyz, 3, where, "origin xyz", _ZERO3)
               + numbers(raw.rpy, 3, where, "origin rpy", _ZERO3))
    axis = numbers(raw.axis, 3, where, "axis xyz", _X_AXIS)
    lower = upper = effort = velocity = damping = friction = mimic = None
    if raw.seen & SEEN_LIMIT:
        effort = number(raw.effort, where, "limit effort")
        velocity = number(raw.velocity, where, "limit velocity")
        if jtype == "revolute" or jtype == "prismatic":
            # URDF: lower/upper default to 0 when <limit> is present but an attribute is not
            lower = _limit("0" if raw.lower is None else raw.lower, where, "limit lower")
            upper = _limit("0" if raw.upper is None else raw.upper, where, "limit upper")
            if lower is not None and upper is not None and lower > upper:
                raise InputError(f"{where}: limit lower {lower} > upper {upper}")
    if raw.seen & SEEN_DYNAMICS:
        damping = number(raw.damping, where, "dynamics damping")
        friction = number(raw.friction, where, "dynamics friction")
    if raw.seen & SEEN_MIMIC:
        if not raw.mimic:
            raise InputError(f"{where}: <mimic> has no joint attribute")
        mult = number(raw.multiplier, where, "mimic multiplier")
        off = number(raw.offset, where, "mimic offset")
        mimic = mimic_type(raw.mimic, 1.0 if mult is None else mult, 0.0 if off is None else off)
    return joint_type(name, jtype, raw.parent, raw.child, None, axis, lower, upper, mimic,
                     effort, velocity, damping, friction, xyz_rpy)


def scan_urdf(str text, str src, object joint_type, object mimic_type):
    """(robot name or None, link names, joints) of URDF text, read in file order and checked one by one.

    The joints are made as ``joint_type(name, type, parent, child, None, axis, lower, upper, mimic, effort,
    velocity, damping, friction, xyz_rpy)`` and their mimics as ``mimic_type(joint, multiplier, offset)``:
    the reader passes its classes (``io.trees.tree_joint.UrdfJoint``, ``body_parts.Mimic``), which live
    in layers above the compiled core.

    Refuses, with an InputError naming ``src``: XML that is not well-formed (line and column), a DTD,
    nesting deeper than MAX_DEPTH, xacro elements, a root other than <robot>, a link without a name or
    with a name used before, no links at all, any joint whose attributes are missing or malformed, and
    joints that do not join the links into one tree (messages name the joint or link).
    """
    cdef _Scan s = _run(text, src)
    if s.xacro:
        name = os.path.basename(src)
        raise InputError(f"{src}: contains xacro macros; give the file a .xacro extension and, if you trust it, "
                         f"pass allow_xacro=True, or expand it first: xacro {name} > robot.urdf")
    if s.root_tag != "robot":
        raise InputError(f"{src}: root element is <{_etree_tag(s.root_tag)}>; a URDF has <robot>")
    known = set()
    cdef Py_ssize_t i
    for i, name in enumerate(s.links):
        if not name:
            raise InputError(f"{src}: link #{i + 1} has no name attribute")
        if name in known:
            raise InputError(f"{src}: duplicate link name(s) '{name}'")
        known.add(name)
    if not s.links:
        raise InputError(f"{src}: no <link> elements; a URDF robot needs links joined by joints")
    joints = [_joint(raw, src, i, joint_type, mimic_type) for i, raw in enumerate(s.joints)]
    _check_tree(s.links, joints, known, src)
    return s.robot_name, tuple(s.links), tuple(joints)


cdef _check_tree(list links, list joints, set known, str src):
    """InputError unless the joints join the links into one tree (names unique, links known)."""
    names = set()
    for j in joints:
        if j.name in names:
            raise InputError(f"{src}: duplicate joint name(s) '{j.name}'")
        names.add(j.name)
    cdef dict parent_of = {}
    cdef dict kids = {}
    for j in joints:
        if j.parent not in known:
            raise InputError(f"{src}: joint '{j.name}': parent link {quote(j.parent)} is not a <link> of the file")
        if j.child not in known:
            raise InputError(f"{src}: joint '{j.name}': child link {quote(j.child)} is not a <link> of the file")
        if j.parent == j.child:
            raise InputError(f"{src}: joint '{j.name}': parent and child are the same link '{j.child}'")
        if j.child in parent_of:
            raise InputError(f"{src}: link '{j.child}' has two parent joints, '{parent_of[j.child]}' and "
                             f"'{j.name}'; a URDF is a tree")
        parent_of[j.child] = j.name
        kids.setdefault(j.parent, []).append(j.child)
    roots = [name for name in links if name not in parent_of]
    if not roots:
        raise InputError(f"{src}: the joints form a cycle (every link has a parent); a URDF is a tree")
    reach = {roots[0]}
    stack = [roots[0]]
    while stack:
        for child in kids.get(stack.pop(), ()):
            reach.add(child)
            stack.append(child)
    if len(reach) < len(links):
        cyc = [name for name in links if name not in reach and name in parent_of]
        if len(roots) == 1 and cyc:
            raise InputError(f"{src}: the joints form a cycle through link(s) {', '.join(cyc[:6])}; a URDF is a tree")
        raise InputError(f"{src}: the links are not connected: several root links "
                         f"({', '.join(roots[:8])}); join them with joints or remove the extra ones")


cdef str _etree_tag(str tag):
    """expat's "uri}local" as xml.etree writes it, "{uri}local"."""
    return "{" + tag if "}" in tag else tag

