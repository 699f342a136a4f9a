"""Personal access tokens of the signed-in user (the IDE's user menu; `melfa users token`
from a shell): list, make, revoke. A revoked token stops working at once, open WebSocket
and rosbridge connections included (they re-check their credentials)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path

from melfa.store import AccessToken
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import Ok, TokenCreatedOut, TokenIn, TokenList, TokenOut

router = APIRouter(prefix="/api/tokens", tags=["tokens"], responses=ERROR_RESPONSES)


def token_out(token: AccessToken) -> TokenOut:
    return TokenOut(
        id=token.id, label=token.label, created=token.created, last_used=token.last_used
    )


@router.get("", response_model=TokenList, summary="My personal access tokens")
async def list_tokens(session: SessionDep, context: ContextDep) -> TokenList:
    found = await context.db(context.store.tokens.list, session.user)
    return TokenList(tokens=[token_out(t) for t in found])


@router.post("", response_model=TokenCreatedOut, status_code=201, summary="Make a token")
async def create_token(body: TokenIn, session: SessionDep, context: ContextDep) -> TokenCreatedOut:
    made = await context.db(context.store.tokens.create, session.user, body.label)
    return TokenCreatedOut(token=made.token, info=token_out(made.info))


@router.delete("/{number}", response_model=Ok, summary="Revoke a token")
async def revoke_token(
    number: Annotated[int, Path(ge=1)], session: SessionDep, context: ContextDep
) -> Ok:
    await context.db(context.store.tokens.revoke, session.user, number)
    context.guard.revoke_session(f"pat-{number}", "the access token was revoked")
    return Ok()


__all__ = ["router"]
