"""Accounts for staff, mirroring `melfa users list|add|import|remove|passwd`: the
instructor's desk in the IDE. Who may manage whom is one rule, `Role.may_manage` (admins
everyone, instructors students), asked by `_manageable` for every change here. Every change
is audited (`melfa.vocab.desk.DeskAction`); a generated password is returned once, never
stored in clear."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path

from melfa.store import Role, Session, User, generate_password
from melfa.store.enrol import EnrolmentError, enrol, parse_enrolment
from melfa.vocab.desk import DESK_WORDS, DeskAction
from melfa.vocab.roles import role_words
from melfa.web.context import WebContext
from melfa.web.convert import user_out
from melfa.web.deps import ContextDep, StaffDep
from melfa.web.desk_audit import audit_desk
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import (
    EnrolIn,
    EnrolOut,
    Ok,
    PasswordIn,
    PasswordOut,
    UserCreatedOut,
    UserCreateIn,
    UserList,
)

router = APIRouter(prefix="/api/users", tags=["users"], responses=ERROR_RESPONSES)

Username = Annotated[str, Path(max_length=200)]


def _refuse(session: Session, role: Role) -> ApiError:
    return ApiError(
        403,
        "forbidden",
        DESK_WORDS["not-yours"].format(
            role=role_words(session.user.role.value).lower(),
            other=role_words(role.value).lower(),
        ),
    )


async def _manageable(context: WebContext, session: Session, username: str) -> User:
    """The account ``username`` when ``session`` may manage it; 404 or 403 otherwise."""
    user = await context.db(context.store.accounts.get_user, username)
    if not session.user.role.may_manage(user.role):
        raise _refuse(session, user.role)
    return user


@router.get("", response_model=UserList, summary="The accounts you may manage")
async def list_users(session: StaffDep, context: ContextDep) -> UserList:
    """Admins: every account; instructors: the students."""
    users = await context.db(context.store.accounts.list_users)
    return UserList(users=[user_out(u) for u in users if session.user.role.may_manage(u.role)])


@router.post("", response_model=UserCreatedOut, status_code=201, summary="Add an account")
async def add_user(body: UserCreateIn, session: StaffDep, context: ContextDep) -> UserCreatedOut:
    if not session.user.role.may_manage(Role(body.role)):
        raise _refuse(session, Role(body.role))
    generated = generate_password() if body.password is None else None
    password = body.password if body.password is not None else generated
    assert password is not None
    user = await context.hash(
        context.store.accounts.create_user,
        body.username,
        password,
        role=Role(body.role),
        group=body.group or None,
        display_name=body.display_name,
    )
    await audit_desk(context, session, DeskAction.ACCOUNT_ADD, who=user.username)
    return UserCreatedOut(user=user_out(user), password=generated)


@router.post("/import", response_model=EnrolOut, summary="Import a class list (CSV)")
async def import_users(body: EnrolIn, session: StaffDep, context: ContextDep) -> EnrolOut:
    """The file `melfa users import` reads; every row is checked first and the import is
    all rows or none. Existing accounts are left as they are."""
    try:
        rows = parse_enrolment(body.csv)
    except EnrolmentError as err:
        raise ApiError(
            422,
            "invalid-value",
            str(err),
            where={"field": "csv"},
            detail={"problems": [{"line": e.line, "message": e.message} for e in err.errors]},
        ) from None
    for row in rows:
        if not session.user.role.may_manage(row.user.role):
            raise _refuse(session, row.user.role)
    report = await context.hash(enrol, context.store.accounts, rows)
    await audit_desk(context, session, DeskAction.ACCOUNT_IMPORT, count=len(report.created))
    return EnrolOut(created=report.created, skipped=report.skipped, passwords=report.generated)


@router.delete("/{username}", response_model=Ok, summary="Remove an account")
async def remove_user(username: Username, session: StaffDep, context: ContextDep) -> Ok:
    if username.strip().lower() == session.user.username:
        raise ApiError(409, "refused", "you cannot remove your own account while signed in")
    user = await _manageable(context, session, username)
    await context.db(context.store.accounts.remove_user, user.username)
    context.guard.revoke_user(user.username, "the account was removed")
    await audit_desk(context, session, DeskAction.ACCOUNT_REMOVE, who=user.username)
    return Ok()


@router.put("/{username}/password", response_model=PasswordOut, summary="Set a password")
async def set_password(
    username: Username, body: PasswordIn, session: StaffDep, context: ContextDep
) -> PasswordOut:
    """The user is signed out everywhere."""
    user = await _manageable(context, session, username)
    generated = generate_password() if body.password is None else None
    password = body.password if body.password is not None else generated
    assert password is not None
    await context.hash(context.store.accounts.set_password, user.username, password)
    context.guard.revoke_user(user.username, "the password was changed")
    await audit_desk(context, session, DeskAction.ACCOUNT_PASSWORD, who=user.username)
    return PasswordOut(password=generated)


__all__ = ["router"]
