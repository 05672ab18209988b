"""The one family protocol: inputs → the member theorem they select.

A theorem whose block structure depends on its inputs (the number of modes, of subsystems, of a
polytope's vertices, the maximum number of losses N, a polynomial degree) is a family of
*members*, one per *key* the inputs select.  :func:`specialise` is the only implementation of
"inputs → member" (``numeric.instance.bind`` is its one caller); what differs between kinds of
family is their :class:`MemberRule`:

* index sets (:class:`~lmidsl.theorem.index_set.IndexSetRule`): the key is the sizes of the
  index sets, read off the data;
* an integer rebuild (:class:`~lmidsl.theorem.family.IntegerRule`, :class:`TheoremFamily`): the
  key is the integer the theorem file's ``build(thm, N)`` loop takes;
* the simplex expansion (:class:`~lmidsl.theorem.robust.SimplexRule`, :class:`RobustTheorem`):
  the key is the simplices' vertex counts, the degree and Pólya's exponent.

A rule reads the key (one-line errors naming the input at fault) and refuses, before anything is
built, a member past the limits of :mod:`lmidsl.theorem.budget` where its size can be estimated
from the statement; :func:`specialise` builds each member once per key and per declaration (the
theorem's fingerprint: a theorem changed after a solve builds afresh), then lets the rule admit
it (a member whose size is known only once built is checked then).  A new kind of family is one
new rule.
"""
from __future__ import annotations


class MemberRule:
    """How a kind of family selects and builds its members (see the module docstring)."""

    def key(self, theorem, inputs: dict) -> tuple:
        """The member's key from the inputs, checked; a member past the limits refused here when
        its size is known from the statement."""
        raise NotImplementedError

    def build(self, theorem, key: tuple):
        """The member theorem for ``key`` (an ordinary :class:`~lmidsl.theorem.theorem.Theorem`)."""
        raise NotImplementedError

    def admit(self, theorem, member, inputs: dict):
        """``member``, once built, for these inputs (a check that needs the built member)."""
        return member


def specialise(theorem, inputs: dict):
    """The theorem for these inputs: itself when it is no family (``member_rule()`` None), else
    its member for the key the inputs select (:func:`built_member`), admitted by the rule."""
    rule = theorem.member_rule()
    if rule is None:
        return theorem
    return rule.admit(theorem, built_member(theorem, rule, rule.key(theorem, inputs)), inputs)


def built_member(theorem, rule: MemberRule, key: tuple):
    """The member for ``key``, built once per key and declaration (the theorem's fingerprint: a
    theorem changed after a solve builds afresh)."""
    stamp = (key, theorem.fingerprint())
    members = theorem.__dict__.setdefault("_members", {})
    if stamp not in members:
        members[stamp] = rule.build(theorem, key)
    return members[stamp]


__all__ = ["MemberRule", "specialise", "built_member"]
