// REST client: CSRF header on state-changing requests, the API's one error shape turned into
// an ApiError with a sentence people can read (docs/api.md "Error shape").

let csrfToken = "";

/** The CSRF token: from the last session reply, else the readable melfa_csrf cookie. */
export function csrf() {
  if (csrfToken) return csrfToken;
  const cookie = document.cookie.split("; ").find((c) => c.startsWith("melfa_csrf="));
  return cookie ? decodeURIComponent(cookie.slice("melfa_csrf=".length)) : "";
}

export function setCsrf(token) {
  csrfToken = token || "";
}

let robotTarget = "lab";

/** The robot every `/api/robot/…` call drives: "lab" or "mine" (docs/api.md "Targets"). */
export function setTarget(id) {
  robotTarget = id;
}

/** `path` with `?target=` added when it is a robot route and the target is not the lab. */
export function targeted(path, target = robotTarget) {
  if (!path.startsWith("/api/robot/") || target === "lab" || path.includes("target=")) return path;
  return path + (path.includes("?") ? "&" : "?") + "target=" + encodeURIComponent(target);
}

export class ApiError extends Error {
  constructor(status, error) {
    super(error?.message || `request failed (HTTP ${status})`);
    this.status = status;
    this.code = error?.code || "http-" + status;
    this.where = error?.where || null;
    this.detail = error?.detail || null;
  }
}

/** An ApiError for "the server could not be reached" (no HTTP status at all). */
export class OfflineError extends ApiError {
  constructor(cause) {
    super(0, { code: "offline", message: "The server cannot be reached. Your edits are kept in this browser." });
    this.cause = cause;
  }
}

/**
 * Call the API. `body` is sent as JSON (or as is for FormData). Returns the parsed JSON
 * (or the Response when `raw`). Throws ApiError / OfflineError; a lost session goes to
 * the sign-in page.
 */
export async function api(method, path, body = undefined, { raw = false, signal } = {}) {
  const headers = {};
  let payload;
  if (body instanceof FormData) payload = body;
  else if (body !== undefined) {
    headers["Content-Type"] = "application/json";
    payload = JSON.stringify(body);
  }
  if (!["GET", "HEAD", "OPTIONS"].includes(method)) headers["X-CSRF-Token"] = csrf();
  let response;
  try {
    response = await fetch(targeted(path), { method, headers, body: payload, credentials: "same-origin", signal });
  } catch (err) {
    if (err?.name === "AbortError") throw err;
    throw new OfflineError(err);
  }
  if (response.ok) {
    if (raw) return response;
    if (response.status === 204) return null;
    const type = response.headers.get("content-type") || "";
    return type.includes("json") ? response.json() : response.text();
  }
  let error = null;
  try {
    error = (await response.json()).error;
  } catch {
    /* not our JSON: keep the status */
  }
  if (response.status === 401 && error?.code === "not-signed-in") {
    location.href = "/login?next=" + encodeURIComponent(location.pathname);
  }
  throw new ApiError(response.status, error);
}

/** A browser download of text, named `filename`. */
export function downloadText(text, filename, type = "text/plain") {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = Object.assign(document.createElement("a"), { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
