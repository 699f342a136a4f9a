"""`melfa users …`: accounts and lab groups in the server's database.

The database is ``DIR/melfa.sqlite3`` with DIR from ``--data``, else ``$MELFA_DATA``,
else ``./data``; the same file `melfa serve` uses, and safe to change while it runs.

Exit codes: 0 done; 1 refused (the name is taken or unknown, the last admin, bad rows in an
enrolment file, a declined confirmation); 2 usage (a bad value or option, a missing or
unreadable file or database).
"""

from __future__ import annotations

import csv
import json
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from melfa.cli.typer_app import app
from melfa.store import (
    DATA_ENV,
    DatabaseError,
    EnrolmentError,
    InvalidValue,
    Role,
    Store,
    StoreError,
    User,
    UserInputError,
    enrol,
    generate_password,
    parse_enrolment,
)

EXIT_REFUSED = 1
EXIT_USAGE = 2

_out = Console(highlight=False, soft_wrap=True, emoji=False)
_err = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)

users_app = typer.Typer(
    name="users",
    help="Manage accounts: add, remove, passwd, list, import a class list.",
    no_args_is_help=True,
)
app.add_typer(users_app, name="users")


def _fail(message: str, code: int) -> typer.Exit:
    _err.print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(code)


DataOpt = Annotated[
    Path,
    typer.Option(
        "--data",
        envvar=DATA_ENV,
        help="Data directory holding melfa.sqlite3 (default ./data, or $MELFA_DATA).",
        file_okay=False,
    ),
]
PasswordStdinOpt = Annotated[
    bool, typer.Option("--password-stdin", help="Read the password from the first line of stdin.")
]
GenerateOpt = Annotated[
    bool, typer.Option("--generate", help="Generate a password and print it once.")
]


@contextmanager
def _store(data: Path, *, create: bool) -> Iterator[Store]:
    """Open the store; every store error becomes one message and an exit code."""
    try:
        store = Store.open_dir(data, create=create)
    except DatabaseError as err:
        hint = "; create the first account with `melfa users add`" if not create else ""
        raise _fail(f"{err}{hint}", EXIT_USAGE) from None
    try:
        yield store
    except InvalidValue as err:
        raise _fail(str(err), EXIT_USAGE) from None
    except UserInputError as err:
        raise _fail(str(err), EXIT_REFUSED) from None
    except StoreError as err:
        raise _fail(str(err), EXIT_USAGE) from None
    finally:
        store.close()


def _password(from_stdin: bool, generate: bool) -> tuple[str, bool]:
    """The new password and whether it was generated (then it must be shown)."""
    if from_stdin and generate:
        raise _fail("--password-stdin and --generate cannot be used together", EXIT_USAGE)
    if from_stdin:
        line = sys.stdin.readline().rstrip("\r\n")
        if not line:
            raise _fail("no password on stdin", EXIT_USAGE)
        return line, False
    if generate or not sys.stdin.isatty():
        return generate_password(), True
    try:
        typed: str = typer.prompt("Password", hide_input=True, confirmation_prompt=True)
    except typer.Abort:
        raise _fail("no password given", EXIT_USAGE) from None
    return typed, False


def _describe(user: User) -> str:
    group = f", group {user.group}" if user.group else ""
    return f"{user.username} ({user.role.value}{group})"


@users_app.command("add")
def add(
    username: Annotated[str, typer.Argument(help="2-32 of a-z 0-9 . _ -")],
    role: Annotated[
        Role, typer.Option("--role", case_sensitive=False, help="What the account may do.")
    ] = Role.STUDENT,
    group: Annotated[
        str | None, typer.Option("--group", help="Lab group (created if new).")
    ] = None,
    name: Annotated[str, typer.Option("--name", help="Display name.")] = "",
    password_stdin: PasswordStdinOpt = False,
    generate: GenerateOpt = False,
    data: DataOpt = Path("data"),
) -> None:
    """Create an account. Asks for the password on a terminal; otherwise generates one."""
    with _store(data, create=True) as store:
        if store.accounts.find_user(username) is not None:
            raise _fail(f"user {username.strip().lower()!r} already exists", EXIT_REFUSED)
        password, generated = _password(password_stdin, generate)
        user = store.accounts.create_user(
            username, password, role=role, group=group, display_name=name
        )
    _err.print(f"created {escape(_describe(user))}")
    if generated:
        _err.print("password (shown only now):")
        _out.print(escape(password))


@users_app.command("passwd")
def passwd(
    username: Annotated[str, typer.Argument()],
    password_stdin: PasswordStdinOpt = False,
    generate: GenerateOpt = False,
    data: DataOpt = Path("data"),
) -> None:
    """Set a new password; the user is signed out everywhere."""
    with _store(data, create=False) as store:
        store.accounts.get_user(username)
        password, generated = _password(password_stdin, generate)
        store.accounts.set_password(username, password)
    _err.print(f"password of {escape(username.strip().lower())} changed; sessions ended")
    if generated:
        _err.print("password (shown only now):")
        _out.print(escape(password))


@users_app.command("remove")
def remove(
    username: Annotated[str, typer.Argument()],
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Do not ask for confirmation.")] = False,
    data: DataOpt = Path("data"),
) -> None:
    """Delete an account, its sessions and its personal workspace."""
    with _store(data, create=False) as store:
        user = store.accounts.get_user(username)
        if not yes:
            try:
                confirmed = typer.confirm(
                    f"Remove {_describe(user)} and their personal workspace?", err=True
                )
            except typer.Abort:
                confirmed = False
            if not confirmed:
                raise _fail("nothing removed", EXIT_REFUSED)
        store.accounts.remove_user(user.username)
    _err.print(f"removed {escape(user.username)}")


@users_app.command("list")
def list_users(
    role: Annotated[Role | None, typer.Option("--role", case_sensitive=False)] = None,
    group: Annotated[str | None, typer.Option("--group")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="One JSON array on stdout.")] = False,
    data: DataOpt = Path("data"),
) -> None:
    """Show the accounts (never their passwords)."""
    with _store(data, create=False) as store:
        users = store.accounts.list_users(role=role, group=group)
    if as_json:
        rows = [
            {
                "username": u.username,
                "name": u.display_name,
                "role": u.role.value,
                "group": u.group,
                "created": u.created.isoformat(),
                "last_login": None if u.last_login is None else u.last_login.isoformat(),
                "disabled": u.disabled,
            }
            for u in users
        ]
        _out.print(json.dumps(rows, indent=2), markup=False)
        return
    table = Table("username", "name", "role", "group", "last login", "status")
    for u in users:
        table.add_row(
            escape(u.username),
            escape(u.display_name),
            u.role.value,
            escape(u.group or ""),
            "never" if u.last_login is None else u.last_login.strftime("%Y-%m-%d %H:%M UTC"),
            "disabled" if u.disabled else "active",
        )
    _out.print(table)
    _err.print(f"{len(users)} account{'s' if len(users) != 1 else ''}")


def _read_csv(path: Path) -> str:
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise _fail(f"{path}: cannot read: {err.strerror or err}", EXIT_USAGE) from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("cp1252", errors="replace")


@users_app.command("import")
def import_users(
    file: Annotated[Path, typer.Argument(help="CSV: username,name,group[,role][,password]")],
    out: Annotated[
        Path | None,
        typer.Option("--out", help="Write generated passwords here (a new file, mode 600)."),
    ] = None,
    update: Annotated[
        bool, typer.Option("--update", help="Update existing accounts instead of skipping them.")
    ] = False,
    data: DataOpt = Path("data"),
) -> None:
    """Enrol a class from a CSV file: all rows or none.

    Rows without a password get a generated one, written to --out for handing out.
    """
    text = _read_csv(file)
    try:
        rows = parse_enrolment(text)
    except EnrolmentError as err:
        for problem in err.errors:
            _err.print(f"{escape(str(file))}:{problem.line}: {escape(problem.message)}")
        raise _fail(str(err), EXIT_REFUSED) from None
    with _store(data, create=True) as store:
        existing = {u.username for u in store.accounts.list_users()}
        needs_password = [
            r for r in rows if not r.password_given and r.user.username not in existing
        ]
        handle = None
        if needs_password:
            if out is None:
                raise _fail(
                    f"{len(needs_password)} new account(s) have no password; pass --out FILE "
                    "to receive the generated ones",
                    EXIT_USAGE,
                )
            try:
                fd = os.open(out, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            except FileExistsError:
                raise _fail(
                    f"{out} already exists; it may hold passwords, so it is not overwritten",
                    EXIT_USAGE,
                ) from None
            except OSError as err:
                raise _fail(f"{out}: cannot create: {err.strerror or err}", EXIT_USAGE) from None
            handle = os.fdopen(fd, "w", newline="", encoding="utf-8")
        try:
            report = enrol(store.accounts, rows, update_existing=update)
        except BaseException:
            if handle is not None and out is not None:
                handle.close()
                out.unlink(missing_ok=True)
            raise
        if handle is not None:
            with handle:
                writer = csv.writer(handle)
                writer.writerow(["username", "name", "group", "password"])
                for username, password in report.generated.items():
                    new = report.rows[username].user
                    writer.writerow([username, new.display_name, new.group or "", password])
    summary = (
        f"created {len(report.created)}, updated {len(report.updated)}, "
        f"skipped {len(report.skipped)}"
    )
    if report.skipped:
        summary += f" (already exist: {', '.join(report.skipped)})"
    _err.print(escape(summary))
    if report.generated and out is not None:
        _err.print(f"{len(report.generated)} generated password(s) written to {escape(str(out))}")


@users_app.command("token")
def token(
    username: Annotated[str, typer.Argument()],
    label: Annotated[
        str, typer.Option("--label", help="What the token is for (shown in lists).")
    ] = "",
    data: DataOpt = Path("data"),
) -> None:
    """Make a personal access token for programs (roslibjs, roslibpy, curl) and print it
    once: `?token=` in a WebSocket URL, rosbridge's auth op, or `Authorization: Bearer`."""
    with _store(data, create=False) as store:
        user = store.accounts.get_user(username)
        made = store.tokens.create(user, label or "cli")
    _err.print(
        f"token {made.info.id} ({escape(made.info.label)}) for {escape(user.username)} "
        "(shown only now; revoke it with `melfa users revoke-token`):"
    )
    _out.print(made.token)


@users_app.command("tokens")
def tokens(
    username: Annotated[str, typer.Argument()],
    data: DataOpt = Path("data"),
) -> None:
    """List a user's personal access tokens (never the tokens themselves)."""
    with _store(data, create=False) as store:
        user = store.accounts.get_user(username)
        found = store.tokens.list(user)
    if not found:
        _err.print(f"{escape(user.username)} has no tokens")
        return
    table = Table("number", "label", "created", "last used")
    for item in found:
        used = item.last_used.strftime("%Y-%m-%d %H:%M") if item.last_used else "never"
        table.add_row(
            str(item.id), escape(item.label), item.created.strftime("%Y-%m-%d %H:%M"), used
        )
    _out.print(table)


@users_app.command("revoke-token")
def revoke_token(
    username: Annotated[str, typer.Argument()],
    number: Annotated[int, typer.Argument(help="The token's number (`melfa users tokens`).")],
    data: DataOpt = Path("data"),
) -> None:
    """Revoke a token: it stops working at once, open connections included."""
    with _store(data, create=False) as store:
        user = store.accounts.get_user(username)
        gone = store.tokens.revoke(user, number)
    _err.print(f"revoked token {gone.id} ({escape(gone.label)}) of {escape(user.username)}")
