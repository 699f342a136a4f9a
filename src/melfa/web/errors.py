"""One error shape for every failing request, and the mapping of each layer's errors to it.

Every JSON error the API sends looks like::

    {"error": {"code": "lease-required", "message": "ann holds the robot; ...",
               "status": 423, "where": null, "detail": {"holder": {...}}}}

``code`` is a stable kebab-case name (documented in docs/api.md), ``message`` a sentence for
people, ``status`` the HTTP status again (datasette's test_error_shape habit), ``where``
points at the cause (``{"field": ...}``, ``{"line": ..., "column": ...}``) or is null, and
``detail`` carries machine-readable extras (the current revision of a conflict, the
diagnostics of a refused file) or is null. Whose fault it is shows in the status: 4xx the
caller's or the controller's refusal, 503 the robot link, 500 ours.
"""

from __future__ import annotations

import logging
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel
from starlette.exceptions import HTTPException as StarletteHTTPException

from melfa.link import LinkError
from melfa.protocol import PositionUnknown
from melfa.protocol.advice import advice_for
from melfa.protocol.errors import LocalProtocolError, ProtocolError
from melfa.robot import ControllerError
from melfa.robot.channel import StopNotConfirmed
from melfa.robot.errors import RobotError, Stopped, UploadRefused
from melfa.service import (
    Cancelled,
    InvalidArgument,
    JogBusy,
    LeaseRequired,
    NoJog,
    NotAllowed,
    Refused,
    ServiceClosed,
    ServiceError,
)
from melfa.store import (
    AccessDenied,
    AlreadyExists,
    AssignmentClosed,
    InvalidValue,
    NotFound,
    SaveConflict,
    StoreError,
    TransferError,
    UserInputError,
    WrongExtension,
)
from melfa.vocab.refusals import Refusal
from melfa.web.pools import Busy

_log = logging.getLogger("melfa.web")

_STATUS_CODES = {
    400: "bad-request",
    401: "not-signed-in",
    403: "forbidden",
    404: "not-found",
    405: "method-not-allowed",
    406: "not-acceptable",
    409: "conflict",
    413: "too-large",
    415: "unsupported-media-type",
    422: "invalid-request",
    423: "locked",
    429: "too-many-requests",
    500: "internal-error",
    503: "unavailable",
}


class ErrorInfo(BaseModel):
    code: str
    message: str
    status: int
    where: dict[str, Any] | None = None
    detail: Any = None


class ErrorBody(BaseModel):
    """The body of every error response."""

    error: ErrorInfo


ERROR_RESPONSES: dict[int | str, dict[str, Any]] = {
    "4XX": {"model": ErrorBody, "description": "Refused: see error.code"},
    "5XX": {"model": ErrorBody, "description": "Server or robot link failure"},
}
"""For `APIRouter(responses=...)`: documents the error shape on every operation."""


class ApiError(Exception):
    """Raised by routes and dependencies; rendered in the one error shape."""

    def __init__(
        self,
        status: int,
        code: str,
        message: str,
        *,
        where: dict[str, Any] | None = None,
        detail: Any = None,
        headers: dict[str, str] | None = None,
    ) -> None:
        super().__init__(message)
        self.status = status
        self.code = code
        self.message = message
        self.where = where
        self.detail = detail
        self.headers = headers

    def body(self) -> dict[str, Any]:
        return {
            "error": {
                "code": self.code,
                "message": self.message,
                "status": self.status,
                "where": self.where,
                "detail": self.detail,
            }
        }

    def response(self) -> JSONResponse:
        return JSONResponse(self.body(), status_code=self.status, headers=self.headers)


def _diagnostics(items: Any) -> list[dict[str, object]]:
    return [d.to_json() for d in items]


def _actor(actor: Any) -> dict[str, str] | None:
    if actor is None:
        return None
    return {"user": actor.user, "role": actor.role.value}


def from_store(exc: StoreError) -> ApiError:
    """A store refusal as an API error; a non-user error is a 500 (ours or the disk's)."""
    message = str(exc)
    if isinstance(exc, SaveConflict):
        current = exc.current
        detail = {
            "base": exc.base,
            "current": {
                "number": current.number,
                "author": current.author,
                "created": current.created.isoformat(),
                "reason": current.reason.value,
                "program": current.program,
                "points": current.points,
            },
        }
        return ApiError(409, "save-conflict", message, detail=detail)
    if isinstance(exc, WrongExtension):
        return ApiError(
            422,
            "wrong-extension",
            message,
            where={"file": exc.filename},
            detail={"expected": exc.expected},
        )
    if isinstance(exc, TransferError):
        first = exc.diagnostics[0] if exc.diagnostics else None
        where: dict[str, Any] = {"file": exc.filename}
        if first is not None:
            where.update(line=first.line, column=first.column)
        return ApiError(
            422,
            "file-not-convertible",
            message,
            where=where,
            detail={"diagnostics": _diagnostics(exc.diagnostics)},
        )
    if isinstance(exc, AssignmentClosed):
        return ApiError(422, "submissions-closed", message, where={"field": exc.field})
    if isinstance(exc, InvalidValue):
        return ApiError(422, "invalid-value", message, where={"field": exc.field})
    if isinstance(exc, NotFound):
        return ApiError(404, "not-found", message)
    if isinstance(exc, AlreadyExists):
        return ApiError(409, "already-exists", message)
    if isinstance(exc, AccessDenied):
        return ApiError(403, "forbidden", message)
    if isinstance(exc, UserInputError):
        return ApiError(400, "refused", message)
    return ApiError(500, "database-error", f"the server's database failed: {message}")


REFUSAL_STATUS: dict[Refusal, int] = {
    Refusal.LEASE_REQUIRED: 423,
    Refusal.LEASE_NOT_TAKEN: 423,
    Refusal.OBSERVER: 403,
    Refusal.PROGRAM_HAS_ERRORS: 422,
    Refusal.POINTS_HAVE_ERRORS: 422,
    Refusal.SIMULATION_REQUIRED: 409,
    Refusal.CELL_CHANGED: 409,
    Refusal.SLOT_CHANGED: 409,
    Refusal.SLOT_UNKNOWN: 409,
    Refusal.QUEUE_ACTIVE: 423,
    Refusal.TURN_OVER: 423,
    Refusal.NOT_YOUR_TURN: 409,
    Refusal.NOT_QUEUED: 409,
    Refusal.HELD: 423,
    Refusal.OUTSIDE_LAB: 403,
}
"""The HTTP status of each policy refusal (the code is the refusal's own)."""
assert set(REFUSAL_STATUS) == set(Refusal), "every refusal has its status"


def from_refusal(exc: Refused) -> ApiError:
    """A policy refusal (`melfa.service.policy`): its code, the same words and fix as every
    other door sends (``message``), the one-click fix a client may offer (``detail.offer``,
    ``detail.fix``, ``detail.fix_label``), the lease's holder, a program's diagnostics."""
    reason = exc.reason
    detail: dict[str, Any] = dict(exc.detail or {})
    if reason.offer is not None:
        detail.update(offer=reason.offer, fix=reason.offer, fix_label=reason.offer_label)
    if exc.asked is not None:  # what was refused: what to do once the fix is done
        detail["asked"] = exc.asked.value
    if isinstance(exc, LeaseRequired):
        detail["holder"] = _actor(exc.holder)
    return ApiError(
        REFUSAL_STATUS[reason], reason.value, str(exc), where=exc.where, detail=detail or None
    )


def from_robot(exc: BaseException) -> ApiError | None:
    """A service, controller or link failure as an API error (None if not one of those)."""
    message = str(exc) or type(exc).__name__
    if isinstance(exc, InvalidArgument):
        # The one 422 for a service call: the caller's argument, named.
        where = {"field": exc.field} if exc.field else None
        return ApiError(422, "invalid-value", message, where=where)
    if isinstance(exc, Refused):
        return from_refusal(exc)
    if isinstance(exc, NotAllowed):
        return ApiError(403, "not-allowed", message)
    if isinstance(exc, JogBusy):
        return ApiError(409, "jog-busy", message)
    if isinstance(exc, NoJog):
        return ApiError(409, "no-jog", message)
    if isinstance(exc, Cancelled | Stopped):
        return ApiError(409, "cancelled", message)
    if isinstance(exc, ServiceClosed):
        return ApiError(503, "service-closed", message)
    if isinstance(exc, ServiceError):
        return ApiError(409, "service-refused", message)
    if isinstance(exc, ControllerError):
        # In the student's words (melfa.protocol.advice), never the request that was sent.
        advice = advice_for(exc.number)
        detail = {"number": exc.number, "controller_message": exc.message, **advice.to_json()}
        if isinstance(exc, UploadRefused):
            return ApiError(
                422,
                "upload-refused",
                f"Line {exc.line}: {advice.message}" if exc.line else advice.message,
                where={"line": exc.line, "column": exc.column},
                detail=detail,
            )
        return ApiError(409, "controller-refused", advice.message, detail=detail)
    if isinstance(exc, LocalProtocolError):
        return ApiError(422, "not-sendable", message)
    if isinstance(exc, ProtocolError):
        _log.warning("garbled controller reply: %s", message)
        return ApiError(
            502,
            "garbled-reply",
            "The controller's answer was garbled. Try again; if it keeps happening, "
            "check the robot's cable.",
        )
    if isinstance(exc, StopNotConfirmed):
        _log.warning("STOP sent, not confirmed: %s", message)
        return ApiError(
            504,
            "stop-not-confirmed",
            "STOP was sent, but the controller did not confirm it: watch the arm, and use "
            "the emergency stop if it still moves.",
        )
    if isinstance(exc, LinkError):
        _log.warning("robot link failed: %s", message)
        return ApiError(
            503,
            "link-down",
            "The robot is not connected right now. melfa keeps reconnecting; "
            "try again in a moment.",
        )
    if isinstance(exc, RobotError):
        return ApiError(422, "robot-refused", message)
    if isinstance(exc, PositionUnknown):
        return ApiError(409, "position-unknown", message)
    return None


def _validation(exc: RequestValidationError) -> ApiError:
    problems = []
    for err in exc.errors():
        loc = [str(p) for p in err.get("loc", ())]
        problems.append({"field": ".".join(loc), "message": str(err.get("msg", "invalid"))})
    first = problems[0] if problems else {"field": "", "message": "invalid request"}
    text = f"{first['field']}: {first['message']}" if first["field"] else first["message"]
    return ApiError(
        422,
        "invalid-request",
        text,
        where={"field": first["field"]} if first["field"] else None,
        detail={"problems": problems},
    )


def install(app: FastAPI) -> None:
    """Register the handlers that turn every failure into the one shape."""

    async def api_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, ApiError)
        return exc.response()

    async def http_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, StarletteHTTPException)
        code = _STATUS_CODES.get(exc.status_code, "error")
        message = exc.detail if isinstance(exc.detail, str) else code
        if exc.status_code == 404 and message == "Not Found":
            message = f"nothing at {request.url.path}"
        headers = dict(exc.headers) if exc.headers else None
        return ApiError(exc.status_code, code, message, headers=headers).response()

    async def validation_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, RequestValidationError)
        return _validation(exc).response()

    async def store_error(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, StoreError)
        error = from_store(exc)
        if error.status >= 500:
            _log.error("store failure on %s %s: %s", request.method, request.url.path, exc)
        return error.response()

    async def robot_error(request: Request, exc: Exception) -> JSONResponse:
        mapped = from_robot(exc)
        assert mapped is not None
        return mapped.response()

    async def busy(request: Request, exc: Exception) -> JSONResponse:
        assert isinstance(exc, Busy)
        return ApiError(503, "busy", str(exc), headers={"Retry-After": "1"}).response()

    async def unexpected(request: Request, exc: Exception) -> JSONResponse:
        _log.exception("unhandled error on %s %s", request.method, request.url.path)
        return ApiError(500, "internal-error", "the server failed; the error was logged").response()

    app.add_exception_handler(ApiError, api_error)
    app.add_exception_handler(StarletteHTTPException, http_error)
    app.add_exception_handler(RequestValidationError, validation_error)
    app.add_exception_handler(StoreError, store_error)
    app.add_exception_handler(Busy, busy)
    for kind in (ServiceError, RobotError, LinkError, ProtocolError, PositionUnknown):
        app.add_exception_handler(kind, robot_error)
    app.add_exception_handler(Exception, unexpected)


__all__ = ["ERROR_RESPONSES", "ApiError", "ErrorBody", "ErrorInfo", "from_robot", "from_store"]
