// What every signed-in page does first (the IDE, the class view, the instructor's desk):
// ask who is signed in, keep the CSRF token for the requests that follow and show the
// name in the top bar. Null when nobody is (the server sends such a page to /login first)
// or the server could not be reached (said once, in a toast).

import { api, setCsrf } from "./api.js";
import { $, showError } from "./ui.js";
import { IDE_WORDS } from "/vocab.js"; // generated from melfa.vocab.ide

export async function signedIn(nameId) {
  let session;
  try {
    session = await api("GET", "/api/session");
  } catch (err) {
    if (err.status !== 401) showError(IDE_WORDS["server-unreachable"], err);
    return null;
  }
  setCsrf(session.csrf_token);
  $(nameId).textContent = session.user.display_name || session.user.username;
  return session;
}
