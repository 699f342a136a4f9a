"""Accounts for admins, mirroring `melfa users list|add|remove|passwd`."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path

from melfa.store import Role, generate_password
from melfa.web.convert import user_out
from melfa.web.deps import AdminDep, ContextDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Ok, PasswordIn, PasswordOut, UserCreatedOut, UserCreateIn, UserList

router = APIRouter(prefix="/api/users", tags=["users"], responses=ERROR_RESPONSES)

Username = Annotated[str, Path(max_length=200)]


@router.get("", response_model=UserList, summary="Every account")
async def list_users(session: AdminDep, context: ContextDep) -> UserList:
    users = await context.db(context.store.accounts.list_users)
    return UserList(users=[user_out(u) for u in users])


@router.post("", response_model=UserCreatedOut, status_code=201, summary="Add an account")
async def add_user(body: UserCreateIn, session: AdminDep, context: ContextDep) -> UserCreatedOut:
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
    return UserCreatedOut(user=user_out(user), password=generated)


@router.delete("/{username}", response_model=Ok, summary="Remove an account")
async def remove_user(username: Username, session: AdminDep, context: ContextDep) -> Ok:
    if username.strip().lower() == session.user.username:
        raise ApiError(409, "refused", "you cannot remove your own account while signed in")
    await context.db(context.store.accounts.remove_user, username)
    context.guard.revoke_user(username.strip().lower(), "the account was removed")
    return Ok()


@router.put("/{username}/password", response_model=PasswordOut, summary="Set a password")
async def set_password(
    username: Username, body: PasswordIn, session: AdminDep, context: ContextDep
) -> PasswordOut:
    """The user is signed out everywhere."""
    generated = generate_password() if body.password is None else None
    password = body.password if body.password is not None else generated
    assert password is not None
    await context.hash(context.store.accounts.set_password, username, password)
    context.guard.revoke_user(username.strip().lower(), "the password was changed")
    return PasswordOut(password=generated)


__all__ = ["router"]
