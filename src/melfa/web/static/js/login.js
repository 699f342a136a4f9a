// The sign-in page: where to go after, and the username kept after a wrong password.
  const next = new URLSearchParams(location.search).get("next");
  if (next && next.startsWith("/") && !next.startsWith("//")) {
    document.getElementById("next").value = next;
  }
  // Keep the username after a wrong password: only the password is typed again.
  const user = document.getElementById("username");
  const kept = sessionStorage.getItem("melfa.login-user");
  if (kept && !user.value) {
    user.value = kept;
    if (document.querySelector(".error")) document.getElementById("password").focus();
  }
  document.getElementById("login").addEventListener("submit", () => sessionStorage.setItem("melfa.login-user", user.value));
