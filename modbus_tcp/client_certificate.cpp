#include "modbus_tcp/client_certificate.h"

#include <openssl/asn1.h>
#include <openssl/bio.h>
#include <openssl/objects.h>

#include <memory>

namespace tiltgate {

namespace {

template <class T, void (*Free)(T*)>
struct Freeing {
  void operator()(T* p) const { Free(p); }
};
using AsnObject = std::unique_ptr<ASN1_OBJECT, Freeing<ASN1_OBJECT, ASN1_OBJECT_free>>;
using Utf8String = std::unique_ptr<ASN1_UTF8STRING, Freeing<ASN1_UTF8STRING, ASN1_UTF8STRING_free>>;
using Bio = std::unique_ptr<BIO, Freeing<BIO, BIO_free_all>>;

std::string one_line_subject(const X509& certificate) {
  const Bio out(BIO_new(BIO_s_mem()));
  if (!out) return {};
  if (X509_NAME_print_ex(out.get(), X509_get_subject_name(&certificate), 0, XN_FLAG_RFC2253) < 0)
    return {};
  char* text = nullptr;
  const long size = BIO_get_mem_data(out.get(), &text);
  return size > 0 ? std::string(text, std::size_t(size)) : std::string();
}

}  // namespace

ClientCertificate read_client_certificate(const X509& certificate) {
  ClientCertificate read;
  read.subject = one_line_subject(certificate);
  // 1: the dotted numbers only, never a name that happens to match.
  const AsnObject oid(OBJ_txt2obj(std::string(kModbusRoleOid).c_str(), 1));
  if (!oid) return read;
  const int at = X509_get_ext_by_OBJ(&certificate, oid.get(), -1);
  if (at < 0) return read;
  const ASN1_OCTET_STRING* data = X509_EXTENSION_get_data(X509_get_ext(&certificate, at));
  const unsigned char* der = ASN1_STRING_get0_data(data);
  const unsigned char* const end = der + ASN1_STRING_length(data);
  const Utf8String role(d2i_ASN1_UTF8STRING(nullptr, &der, end - der));
  if (!role || der != end) {
    read.role = "";
    read.role_problem = "its role extension holds no UTF8String";
    return read;
  }
  read.role = std::string(reinterpret_cast<const char*>(ASN1_STRING_get0_data(role.get())),
                          std::size_t(ASN1_STRING_length(role.get())));
  return read;
}

}  // namespace tiltgate
